// Fitting the ICT-FaceKit model to one picture: random identities rendered by
// the project's rasterizer, landmarks by dlib, the fit compared with the truth.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <glm/geometric.hpp>

#include "facerig/offline/photo/debug.h"
#include "facerig/offline/photo/landmarks.h"
#include "facerig/offline/error.h"
#include "facerig/offline/photo/fit.h"
#include "facerig/offline/photo/image.h"
#include "facerig/offline/geometry/similarity.h"
#include "facerig/runtime/behaviour/blink.h"
#include "facerig/runtime/rig_builder.h"
#include "facerig/offline/default_head/default_head.h"
#include "support/default_head_poses.h"
#include "support/ict_faces.h"
#include "support/test_meshes.h"

namespace {

using facerig::Pcg32;
using facerig::PhotoFaceModel;
using facerig::RgbImage;

constexpr float kPi = 3.14159265f;

struct IctPhotoSetup {
  facerig::FaceTemplateInfo info;
  PhotoFaceModel model;
};

// One detector for the file: loading dlib's predictor takes a good part of a second.
facerig::LandmarkDetector& Detector() {
  static facerig::LandmarkDetector detector;
  return detector;
}

const IctPhotoSetup& Setup() {
  static const IctPhotoSetup setup = [] {
    IctPhotoSetup s;
    s.info = facerig::test::LoadIctTemplateInfo(facerig::test::IctRig());
    s.model = facerig::BuildPhotoFaceModel(facerig::test::IctRig(), s.info, facerig::test::IctFaces().identities, {},
                                           &Detector());
    return s;
  }();
  return setup;
}

std::vector<glm::vec3> FaceWithWeights(const PhotoFaceModel& model, const std::vector<double>& weights) {
  std::vector<glm::vec3> face = model.neutral;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    for (std::size_t v = 0; v < face.size(); ++v) face[v] += static_cast<float>(weights[i]) * model.identity_modes[i][v];
  }
  return face;
}

glm::vec3 PartColour(const std::string& name) {
  if (name.starts_with("skin")) return {0.86f, 0.66f, 0.55f};
  if (name.starts_with("eyeball")) return {0.85f, 0.85f, 0.82f};
  if (name.starts_with("eyelashes")) return {0.15f, 0.10f, 0.08f};
  if (name == "teeth") return {0.9f, 0.9f, 0.85f};
  return {0.45f, 0.20f, 0.20f};  // mouth and eye sockets, gums
}

// Half the height the photo frames at the nose tip's depth (cm).
constexpr float kHalfFrame = 16.0f;

// The photo's camera looking at the nose tip: orthographic (distance 0) or a
// perspective camera `distance_cm` away, framing the same +-kHalfFrame at the nose tip.
facerig::RasterView PhotoView(glm::vec3 nose, float yaw_degrees, int size, float distance_cm) {
  facerig::RasterView view = facerig::RasterView::Orbit(nose, kHalfFrame, size, size, yaw_degrees * kPi / 180.0f);
  if (distance_cm > 0.0f) {
    view.vertical_fov = 2.0f * std::atan(kHalfFrame / distance_cm);
    view.distance = distance_cm;
  }
  return view;
}

// How a test photo is lit and painted: the default is one light 30 degrees
// above the view axis on a flat skin colour; `blotchy` paints the skin with
// smooth +-10 % blotches and darker brows and lips.
struct RenderStyle {
  glm::vec3 light{0.0f, 0.5f, 0.8660254f};
  float ambient = 0.25f;
  bool blotchy = false;
  // How far the fitted camera's yaw may be off (degrees).
  float yaw_tolerance = 4.0f;
  // Gaussian pixel noise (standard deviation, fractions of full scale).
  float noise = 0.0f;
  // A perspective photo from this far (cm; 0: orthographic).
  float distance_cm = 0.0f;
};

// 40 degrees off the view axis, from the upper left, and little ambient light.
RenderStyle SideLight() {
  const float off = 40.0f * kPi / 180.0f;
  // dlib's points follow the hard shadows: the landmark fit's yaw is off by up to 5 degrees.
  return {glm::vec3(-std::sin(off) * 0.7071f, std::sin(off) * 0.7071f, std::cos(off)), 0.1f, false, 6.0f};
}

RenderStyle Blotchy() { return {.blotchy = true}; }

// All at once: side light, blotchy skin and pixel noise (a camera's at ISO 800 or so).
RenderStyle Hard() {
  RenderStyle style = SideLight();
  style.blotchy = true;
  style.noise = 0.02f;
  return style;
}

void AddNoise(RgbImage& image, float sigma) {
  Pcg32 rng(4242);
  for (std::uint8_t& v : image.pixels) {
    v = static_cast<std::uint8_t>(std::clamp(std::lround(v + 255.0 * sigma * rng.NextNormal()), 0L, 255L));
  }
}

// Smooth blotches in [-1, 1] over the head (cm): a few random plane waves.
float Blotches(glm::vec3 p) {
  static const std::vector<glm::vec4> waves = [] {
    Pcg32 rng(77);
    std::vector<glm::vec4> w;
    for (int k = 0; k < 6; ++k) {
      const glm::vec3 direction = glm::normalize(glm::vec3(rng.NextNormal(), rng.NextNormal(), rng.NextNormal()));
      w.emplace_back(direction * (2.0f * kPi / (3.0f + 2.0f * float(k % 3))), 6.0f * float(rng.NextNormal()));
    }
    return w;
  }();
  float sum = 0.0f;
  for (const glm::vec4& w : waves) sum += std::sin(glm::dot(glm::vec3(w), p) + w.w);
  return std::clamp(sum / 2.5f, -1.0f, 1.0f);
}

float DistanceToSegments(glm::vec3 p, const std::vector<glm::vec3>& points) {
  float best = 1e9f;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) {
    const glm::vec3 d = points[k + 1] - points[k];
    const float t = std::clamp(glm::dot(p - points[k], d) / glm::dot(d, d), 0.0f, 1.0f);
    best = std::min(best, glm::length(p - points[k] - t * d));
  }
  return best;
}

// The skin's colour at triangle centre `p` of a blotchy face: darker brows and lips.
glm::vec3 BlotchySkin(glm::vec3 skin, glm::vec3 p, const facerig::FaceTemplateInfo& info,
                      const std::vector<glm::vec3>& positions) {
  const auto chain = [&](int first, int last, bool closed) {
    std::vector<glm::vec3> points;
    for (int k = first; k <= last; ++k) points.push_back(positions[info.landmark_vertices[std::size_t(k)]]);
    if (closed) points.push_back(points.front());
    return points;
  };
  glm::vec3 colour = skin * (1.0f + 0.1f * Blotches(p));
  if (std::min(DistanceToSegments(p, chain(17, 21, false)), DistanceToSegments(p, chain(22, 26, false))) < 0.5f) {
    colour *= glm::vec3(0.55f, 0.5f, 0.5f);
  }
  if (DistanceToSegments(p, chain(48, 59, true)) < 0.35f) colour *= glm::vec3(0.85f, 0.65f, 0.65f);
  return colour;
}

// The head rendered with Lambert light; the eye films (transparent in ICT) left out.
RgbImage RenderFace(const facerig::FaceTemplateInfo& info, const std::vector<glm::vec3>& positions, float yaw_degrees,
                    int size, const RenderStyle& style = {}) {
  facerig::Mesh mesh{.positions = positions};
  std::vector<glm::vec3> albedo;
  for (const facerig::Triangle& t : facerig::test::IctRig().triangles()) {
    const facerig::TemplatePart* part = nullptr;
    for (const facerig::TemplatePart& p : info.parts) {
      if (t[0] >= p.vertices.first && t[0] <= p.vertices.last) part = &p;
    }
    if (part == nullptr || part->name.starts_with("lacrimal") || part->name.starts_with("eye_blend") ||
        part->name.starts_with("eye_occlusion")) {
      continue;
    }
    mesh.triangles.push_back(t);
    albedo.push_back(PartColour(part->name));
    if (style.blotchy && part->name.starts_with("skin")) {
      albedo.back() = BlotchySkin(albedo.back(), (positions[t[0]] + positions[t[1]] + positions[t[2]]) / 3.0f, info,
                                  positions);
    }
  }
  std::vector<glm::vec3> normals(positions.size());
  facerig::ComputeVertexNormals(positions, mesh.triangles, normals);
  for (const facerig::Triangle& t : mesh.triangles) {
    for (const std::uint32_t v : t) mesh.corner_normals.push_back(normals[v]);
  }
  const facerig::RasterView view = PhotoView(positions[info.landmark_vertices[30]], yaw_degrees, size, style.distance_cm);
  facerig::ShadeParams shade;
  shade.light = style.light;
  shade.ambient = style.ambient;
  RgbImage image = facerig::Shade(facerig::Rasterize(mesh, view), mesh, albedo, view, shade);
  if (style.noise > 0.0f) AddNoise(image, style.noise);
  return image;
}

// Mean distance (mm; ICT is in cm) over the face group after the best similarity alignment.
double FaceErrorMm(const std::vector<glm::vec3>& fitted, const std::vector<glm::vec3>& truth, facerig::VertexRange face) {
  const std::span<const glm::vec3> a(fitted.data() + face.first, face.count());
  const std::span<const glm::vec3> b(truth.data() + face.first, face.count());
  const facerig::SimilarityTransform align = facerig::Umeyama(a, b);
  double sum = 0.0;
  for (std::size_t v = 0; v < a.size(); ++v) sum += glm::length(align.Apply(a[v]) - b[v]);
  return 10.0 * sum / static_cast<double>(a.size());
}

// The truth's least-squares projection on the identity modes over the face.
std::vector<glm::vec3> ProjectOnModes(const PhotoFaceModel& model, const std::vector<glm::vec3>& truth,
                                      facerig::VertexRange face) {
  const auto n = static_cast<Eigen::Index>(model.identity_modes.size());
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
  for (std::uint32_t v = face.first; v <= face.last; ++v) {
    const glm::vec3 d = truth[v] - model.neutral[v];
    for (Eigen::Index i = 0; i < n; ++i) {
      const glm::vec3 mi = model.identity_modes[static_cast<std::size_t>(i)][v];
      rhs[i] += glm::dot(mi, d);
      for (Eigen::Index j = 0; j <= i; ++j) normal(i, j) += glm::dot(mi, model.identity_modes[static_cast<std::size_t>(j)][v]);
    }
  }
  normal = normal.selfadjointView<Eigen::Lower>();
  const Eigen::VectorXd w = normal.ldlt().solve(rhs);
  return FaceWithWeights(model, std::vector<double>(w.data(), w.data() + w.size()));
}

std::vector<glm::vec3> WithExpression(const PhotoFaceModel& model, std::vector<glm::vec3> face, const std::string& name,
                                      float weight) {
  for (std::size_t e = 0; e < model.expression_names.size(); ++e) {
    if (model.expression_names[e] != name) continue;
    for (std::size_t v = 0; v < face.size(); ++v) face[v] += weight * model.expression_deltas[e][v];
  }
  return face;
}

float ExpressionWeight(const facerig::PhotoFit& fit, const std::string& name) {
  for (std::size_t e = 0; e < fit.expression_names.size(); ++e) {
    if (fit.expression_names[e] == name) return fit.expression_weights[e];
  }
  return 0.0f;
}

// Degrees the camera turned about world +y (RasterView::Orbit's sense).
float Yaw(const facerig::ScaledOrthoCamera& camera) {
  const glm::vec3 forward(camera.rotation[0][2], camera.rotation[1][2], camera.rotation[2][2]);
  return std::atan2(forward.x, forward.z) * 180.0f / kPi;
}

// The RasterView puts every fitted landmark vertex where the camera does.
void CheckCameraMatchesRasterView(const facerig::PhotoFit& fit) {
  for (std::size_t k = 0; k < fit.landmark_vertices.size(); ++k) {
    const glm::vec3 p = facerig::ProjectToImage(fit.view, fit.posed_positions[fit.landmark_vertices[k]]);
    CHECK(glm::length(glm::vec2(p) - fit.model_pixels[k]) < 0.01f);
  }
}

struct Errors {
  double fit = 0.0, mean_face = 0.0, best = 0.0, fit_seconds = 0.0;
  double camera_distance = 0.0;  // the fits' mean (0: orthographic)
  int count = 0;
};

// The landmark vertices' exact projections into a render of `rendered`: what
// a perfect detector would give (the jaw at its fixed vertices).
std::vector<glm::vec2> ExactLandmarks(const facerig::FaceTemplateInfo& info, const std::vector<glm::vec3>& rendered,
                                      float yaw_degrees, int size, float distance_cm) {
  const facerig::RasterView view = PhotoView(rendered[info.landmark_vertices[30]], yaw_degrees, size, distance_cm);
  std::vector<glm::vec2> pixels;
  for (const std::uint32_t v : info.landmark_vertices) pixels.emplace_back(facerig::ProjectToImage(view, rendered[v]));
  return pixels;
}

// jaw_open: the photo's jawOpen weight (the fit must still give the rest face).
// exact: the fit takes ExactLandmarks instead of dlib's (no offsets, fixed jaw).
// params.shading: the fit refined by RefinePhotoFitByShading; style.distance_cm: a perspective photo.
Errors MeasureFits(int faces, float yaw_degrees, std::uint64_t seed, const facerig::PhotoFitParams& params = {},
                   float jaw_open = 0.0f, bool exact = false, const RenderStyle& style = {}) {
  const float distance_cm = style.distance_cm;
  const IctPhotoSetup& setup = Setup();
  const facerig::VertexRange face = setup.info.Group("face");
  facerig::LandmarkDetector& detector = Detector();
  Pcg32 rng(seed);
  Errors errors;
  for (int f = 0; f < faces; ++f) {
    std::vector<double> weights(setup.model.identity_modes.size());
    for (double& w : weights) w = rng.NextNormal();
    const std::vector<glm::vec3> truth = FaceWithWeights(setup.model, weights);
    const std::vector<glm::vec3> rendered = WithExpression(setup.model, truth, "jawOpen", jaw_open);
    const RgbImage photo = RenderFace(setup.info, rendered, yaw_degrees, 512, style);
    facerig::PhotoLandmarks landmarks = facerig::DetectPhotoLandmarks(detector, photo);
    facerig::PhotoFitParams used = params;
    if (exact) {
      landmarks.pixels = ExactLandmarks(setup.info, rendered, yaw_degrees, photo.width, distance_cm);
      used.remove_landmark_offsets = false;
      used.moving_contour = false;
      // Noise-free points: only the prior holds the shape back.
      used.landmark_sigma_fraction = 0.004;
      used.jaw_weight = used.brow_weight = used.eye_weight = 1.0f;
      used.shading = false;
    }
    const facerig::PhotoFit fit = facerig::FitPhoto(setup.model, photo, landmarks.pixels, used);
    if (f == 0) {
      const std::string distance = distance_cm > 0.0f ? "_" + std::to_string(int(distance_cm)) + "cm" : "";
      facerig::WritePhotoFitPng(
          facerig::test::OutputPath("photo_fit_yaw" + std::to_string(int(yaw_degrees)) + distance + ".png"), photo,
          landmarks, fit);
    }
    errors.fit += FaceErrorMm(fit.rest_positions, truth, face);
    errors.mean_face += FaceErrorMm(setup.model.neutral, truth, face);
    errors.best += FaceErrorMm(ProjectOnModes(setup.model, truth, face), truth, face);
    errors.fit_seconds = std::max(errors.fit_seconds, fit.seconds);
    errors.camera_distance += fit.camera_distance / double(faces);
    CheckCameraMatchesRasterView(fit);
    CHECK(std::abs(Yaw(fit.camera) - yaw_degrees) < style.yaw_tolerance);
    if (jaw_open > 0.0f) CHECK(ExpressionWeight(fit, "jawOpen") > 0.5f * jaw_open);
    ++errors.count;
  }
  errors.fit /= faces;
  errors.mean_face /= faces;
  errors.best /= faces;
  std::printf("photo fit, yaw %2.0f, %s, %d faces: fit %.3f mm, mean face %.2f mm, best %.3f mm; slowest fit %.1f ms; "
              "fitted camera distance %.0f\n",
              double(yaw_degrees), distance_cm > 0.0f ? (std::to_string(int(distance_cm)) + " cm").c_str() : "ortho",
              faces, errors.fit, errors.mean_face, errors.best, 1e3 * errors.fit_seconds, errors.camera_distance);
  return errors;
}

}  // namespace

// The goal (<= 1.5 mm and half the mean face's error): the landmark fit
// alone removes about a quarter of the mean face's error (dlib's scatter; the
// landmark vertices' exact projections would reach about 1.1 mm), the shading
// refinement (the default) reaches it on these renders (numbers from
// "[.measure]" in the report; these two faces are easier than the average).
TEST_CASE("Photo fit recovers random ICT identities from renders (shared data)", "[photo_fit][shared-data][accuracy]") {
  facerig::PhotoFitParams landmarks_only;
  landmarks_only.shading = false;
  for (const float yaw : {0.0f, 15.0f}) {
    const Errors landmarks = MeasureFits(2, yaw, 17, landmarks_only);
    CHECK(landmarks.best < 0.05);
    CHECK(landmarks.fit < 0.9 * landmarks.mean_face);
    const Errors refined = MeasureFits(2, yaw, 17);
    CHECK(refined.fit < 1.5);
    CHECK(refined.fit < 0.5 * refined.mean_face);
    CHECK(refined.fit < 0.85 * landmarks.fit);
  }
}

// A selfie: at 35 cm the orthographic fit of the exact landmark projections
// is several times worse than the perspective one, which finds the distance
// (from the landmarks' centroid, a few cm behind the nose tip the render is 35 cm from).
TEST_CASE("Photo fit of a selfie-distance render picks a perspective camera (shared data)",
          "[photo_fit][photo_perspective][shared-data]") {
  facerig::PhotoFitParams orthographic;
  orthographic.camera_distances.clear();
  const Errors flat = MeasureFits(2, 0.0f, 17, orthographic, 0.0f, true, {.distance_cm = 35.0f});
  const Errors perspective = MeasureFits(2, 0.0f, 17, {}, 0.0f, true, {.distance_cm = 35.0f});
  CHECK(flat.camera_distance == 0.0);
  CHECK(perspective.fit < 0.5 * flat.fit);
  CHECK(perspective.camera_distance > 30.0);
  CHECK(perspective.camera_distance < 50.0);
}

TEST_CASE("Photo shading fit refuses bad input and leaves a deformed fit as it is (shared data)",
          "[photo_fit][shared-data]") {
  const IctPhotoSetup& setup = Setup();
  const RgbImage photo = RenderFace(setup.info, setup.model.neutral, 0.0f, 256);
  const facerig::PhotoLandmarks landmarks = facerig::DetectPhotoLandmarks(Detector(), photo);
  const facerig::PhotoFit fit = facerig::FitPhoto(setup.model, landmarks.pixels, photo.width, photo.height);
  CHECK_THROWS_AS(facerig::RefinePhotoFitByShading(setup.model, photo, std::span(landmarks.pixels).first(10), fit),
                  facerig::InvalidInputError);
  RgbImage broken = photo;
  broken.pixels.resize(10);
  CHECK_THROWS_AS(facerig::RefinePhotoFitByShading(setup.model, broken, landmarks.pixels, fit),
                  facerig::InvalidInputError);
  PhotoFaceModel expressions_only = setup.model;
  expressions_only.identity_modes.clear();
  const facerig::PhotoFit deformed = facerig::FitPhoto(expressions_only, landmarks.pixels, photo.width, photo.height);
  const facerig::PhotoFit same =
      facerig::RefinePhotoFitByShading(expressions_only, photo, landmarks.pixels, deformed);
  CHECK(same.posed_positions == deformed.posed_positions);
  CHECK(same.lighting.empty());
}

TEST_CASE("Photo shading fit gives the photo's lighting (shared data)", "[photo_fit][shared-data]") {
  const IctPhotoSetup& setup = Setup();
  const RenderStyle style = SideLight();
  const RgbImage photo = RenderFace(setup.info, setup.model.neutral, 0.0f, 384, style);
  const facerig::PhotoLandmarks landmarks = facerig::DetectPhotoLandmarks(Detector(), photo);
  const facerig::PhotoFit fit = facerig::FitPhoto(setup.model, landmarks.pixels, photo.width, photo.height);
  CHECK(fit.lighting.empty());
  const facerig::PhotoFit refined = facerig::RefinePhotoFitByShading(setup.model, photo, landmarks.pixels, fit);
  REQUIRE(refined.lighting.size() == 9);
  // Brighter towards the light (from the upper left) than mirrored to the right.
  const glm::vec3 towards = glm::normalize(style.light), away(-towards.x, towards.y, towards.z);
  const auto luma = [](glm::vec3 c) { return 0.299f * c.r + 0.587f * c.g + 0.114f * c.b; };
  const float lit = luma(facerig::EvaluatePhotoLighting(refined.lighting, towards));
  const float unlit = luma(facerig::EvaluatePhotoLighting(refined.lighting, away));
  INFO("shade towards the light " << lit << ", mirrored " << unlit);
  CHECK(lit > unlit + 0.1f);
}

TEST_CASE("Photo fit of an open mouth gives the rest face (shared data)", "[photo_fit][shared-data]") {
  const Errors e = MeasureFits(1, 0.0f, 5, {}, 0.6f);
  CHECK(e.fit < e.mean_face);
}

TEST_CASE("Photo fit without identity modes deforms the head onto the landmarks (shared data)",
          "[photo_fit][shared-data]") {
  const IctPhotoSetup& setup = Setup();
  PhotoFaceModel model = setup.model;
  model.identity_modes.clear();
  facerig::LandmarkDetector& detector = Detector();
  Pcg32 rng(3);
  std::vector<double> weights(setup.model.identity_modes.size());
  for (double& w : weights) w = rng.NextNormal();
  const std::vector<glm::vec3> truth = FaceWithWeights(setup.model, weights);
  const RgbImage photo = RenderFace(setup.info, truth, 0.0f, 512);
  const facerig::PhotoLandmarks landmarks = facerig::DetectPhotoLandmarks(detector, photo);
  const facerig::PhotoFit fit = facerig::FitPhoto(model, landmarks.pixels, photo.width, photo.height);
  CHECK(fit.deformed);
  CHECK(fit.rms_pixels < 0.5);
  CheckCameraMatchesRasterView(fit);
  const facerig::VertexRange face = setup.info.Group("face");
  const double error = FaceErrorMm(fit.rest_positions, truth, face);
  const double mean_face = FaceErrorMm(model.neutral, truth, face);
  std::printf("photo deform without identity modes: %.2f mm (mean face %.2f mm), %.1f ms\n", error, mean_face,
              1e3 * fit.seconds);
  CHECK(error < 1.2 * mean_face);
}

TEST_CASE("Photo fit with the built-in head deforms it onto a photo's landmarks (shared data)",
          "[photo_fit][shared-data]") {
  const facerig::Rig& head = facerig::test::DefaultHead();
  facerig::FaceTemplateInfo info = facerig::DefaultHeadTemplateInfo(head);
  facerig::LandmarkDetector& detector = Detector();
  info.landmark_vertices = facerig::TemplateLandmarkVertices(head, info, detector);
  const PhotoFaceModel model = facerig::BuildPhotoFaceModel(head, info, {}, {}, &detector);
  CHECK(model.identity_modes.empty());
  CHECK(!model.expression_deltas.empty());
  const RgbImage photo = RenderFace(Setup().info, Setup().model.neutral, 15.0f, 512);
  const facerig::PhotoLandmarks landmarks = facerig::DetectPhotoLandmarks(detector, photo);
  const facerig::PhotoFit fit = facerig::FitPhoto(model, landmarks.pixels, photo.width, photo.height);
  CHECK(fit.deformed);
  CHECK(fit.rms_pixels < 0.5);
  CheckCameraMatchesRasterView(fit);
  facerig::WritePhotoFitPng(facerig::test::OutputPath("photo_fit_default_head.png"), photo, landmarks, fit);
}

TEST_CASE("Scaled orthographic camera from exact 2D-3D pairs", "[photo_fit]") {
  Pcg32 rng(11);
  std::vector<glm::vec3> points;
  for (int k = 0; k < 30; ++k) {
    points.emplace_back(rng.NextNormal() * 5.0, rng.NextNormal() * 5.0, rng.NextNormal() * 2.0);
  }
  facerig::ScaledOrthoCamera truth;
  const glm::vec3 axis = glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f));
  const float angle = 0.4f;  // about 23 degrees
  const float c = std::cos(angle), s = std::sin(angle);
  const glm::mat3 k(0.0f, axis.z, -axis.y, -axis.z, 0.0f, axis.x, axis.y, -axis.x, 0.0f);  // cross-product matrix
  truth.rotation = glm::transpose(glm::mat3(1.0f) + s * k + (1.0f - c) * k * k);
  truth.scale = 12.5f;
  truth.translation = {-20.0f, 35.0f};
  std::vector<glm::vec2> pixels;
  for (const glm::vec3& p : points) pixels.push_back(facerig::ProjectPixel(truth, p, 640, 480));
  const facerig::ScaledOrthoCamera fit = facerig::FitScaledOrthoCamera(points, pixels, {}, 640, 480);
  CHECK(std::abs(fit.scale - truth.scale) < 1e-3f);
  for (int col = 0; col < 3; ++col) {
    CHECK(glm::length(fit.rotation[col] - truth.rotation[col]) < 1e-4f);
  }
  CHECK(glm::length(fit.translation - truth.translation) < 1e-2f);
  // As a RasterView: the same pixels.
  const facerig::RasterView view = facerig::ToRasterView(fit, 640, 480, points[0]);
  for (std::size_t i = 0; i < points.size(); ++i) {
    CHECK(glm::length(glm::vec2(facerig::ProjectToImage(view, points[i])) - pixels[i]) < 1e-2f);
  }
  CHECK_THROWS_AS(facerig::FitScaledOrthoCamera(std::span(points).first(3), std::span(pixels).first(3), {}, 640, 480),
                  facerig::InvalidInputError);
}

TEST_CASE("Photo landmarks take the largest of several faces (shared data)", "[photo_fit][shared-data]") {
  const RgbImage large = RenderFace(Setup().info, Setup().model.neutral, 0.0f, 400);
  const RgbImage small = RenderFace(Setup().info, Setup().model.neutral, 0.0f, 240);
  RgbImage both{.width = 640, .height = 400, .pixels = std::vector<std::uint8_t>(640 * 400 * 3, 40)};
  auto paste = [&](const RgbImage& image, int x0) {
    for (int y = 0; y < image.height; ++y) {
      std::copy_n(image.pixels.begin() + y * image.width * 3, image.width * 3,
                  both.pixels.begin() + (y * both.width + x0) * 3);
    }
  };
  paste(small, 0);
  paste(large, 240);
  facerig::LandmarkDetector& detector = Detector();
  const facerig::PhotoLandmarks landmarks = facerig::DetectPhotoLandmarks(detector, both);
  CHECK(landmarks.faces_found == 2);
  REQUIRE(landmarks.notes.size() == 1);
  CHECK(landmarks.notes[0].find("largest") != std::string::npos);
  CHECK(landmarks.box.left >= 240);
  for (const glm::vec2 p : landmarks.pixels) CHECK(p.x > 240.0f);
}

TEST_CASE("Identity meshes are read from a template folder (shared data)", "[photo_fit][shared-data]") {
  const facerig::Rig& rig = facerig::test::IctRig();
  const auto identities = facerig::LoadIdentityMeshes(facerig::test::IctDir(), rig.vertex_count(), 2);
  REQUIRE(identities.size() == 2);
  CHECK(identities[1] == facerig::test::IctFaces().identities[1]);
  CHECK_THROWS_AS(facerig::LoadIdentityMeshes(facerig::test::IctDir(), 100, 1), facerig::InvalidInputError);
  CHECK(facerig::LoadIdentityMeshes(facerig::test::OutputPath("no_identities_here"), rig.vertex_count()).empty());
}

TEST_CASE("Photo landmarks refuse an image without a face (shared data)", "[photo_fit][shared-data]") {
  facerig::LandmarkDetector& detector = Detector();
  RgbImage blank{.width = 200, .height = 150, .pixels = std::vector<std::uint8_t>(200 * 150 * 3, 90)};
  CHECK_THROWS_AS(facerig::DetectPhotoLandmarks(detector, blank), facerig::LandmarkDetectionError);
  RgbImage broken{.width = 10, .height = 10, .pixels = {}};
  CHECK_THROWS_AS(facerig::DetectPhotoLandmarks(detector, broken), facerig::InvalidInputError);
  // A face dlib finds but smaller than the limit the caller asks for.
  const RgbImage photo = RenderFace(Setup().info, Setup().model.neutral, 0.0f, 256);
  facerig::PhotoLandmarkParams strict;
  strict.min_face_pixels = 400;
  CHECK_THROWS_AS(facerig::DetectPhotoLandmarks(detector, photo, strict), facerig::LandmarkDetectionError);
  CHECK(facerig::DetectPhotoLandmarks(detector, photo).pixels.size() == 68);
}

TEST_CASE("Photo fit accuracy over many faces (shared data)", "[.measure][photo_fit][shared-data]") {
  facerig::PhotoFitParams landmarks_only;
  landmarks_only.shading = false;
  facerig::PhotoFitParams shading;
  shading.shading = true;
  facerig::PhotoFitParams no_self_calibration = landmarks_only;
  no_self_calibration.self_calibration_rounds = 0;
  for (const float yaw : {0.0f, 15.0f}) {
    std::printf("the landmarks only:\n");
    MeasureFits(30, yaw, 1234, landmarks_only);
    std::printf("refined by the shading:\n");
    MeasureFits(30, yaw, 1234, shading);
    for (const auto& [name, style] : {std::pair("side light", SideLight()), std::pair("blotchy albedo", Blotchy()),
                                      std::pair("side light, blotchy albedo and noise", Hard())}) {
      std::printf("%s, without and with the shading term:\n", name);
      MeasureFits(30, yaw, 1234, landmarks_only, 0.0f, false, style);
      MeasureFits(30, yaw, 1234, shading, 0.0f, false, style);
    }
    std::printf("the landmarks only, without the self-calibration:\n");
    MeasureFits(30, yaw, 1234, no_self_calibration);
    std::printf("the landmark vertices' exact projections instead of dlib's:\n");
    MeasureFits(30, yaw, 1234, {}, 0.0f, true);
  }
  auto start = std::chrono::steady_clock::now();
  const auto identities = facerig::LoadIdentityMeshes(facerig::test::IctDir(), facerig::test::IctRig().vertex_count());
  const double load = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  start = std::chrono::steady_clock::now();
  const facerig::PhotoFaceModel model =
      facerig::BuildPhotoFaceModel(facerig::test::IctRig(), Setup().info, identities, {}, &Detector());
  const double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("model: %zu identity meshes read in %.0f ms, built and calibrated in %.0f ms\n", model.identity_modes.size(),
              1e3 * load, 1e3 * build);
  // Detection time on a 1024 px photo (the same detector as the model build's would do).
  facerig::LandmarkDetector& detector = Detector();
  const RgbImage photo = RenderFace(Setup().info, Setup().model.neutral, 0.0f, 1024);
  start = std::chrono::steady_clock::now();
  const facerig::PhotoLandmarks landmarks = facerig::DetectPhotoLandmarks(detector, photo);
  const double detect = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const facerig::PhotoFit fit = facerig::FitPhoto(Setup().model, landmarks.pixels, photo.width, photo.height);
  std::printf("1024 px photo: detection %.0f ms, fit %.1f ms\n", 1e3 * detect, 1e3 * fit.seconds);
  for (const int size : {512, 1024}) {
    const RgbImage shaded = RenderFace(Setup().info, Setup().model.neutral, 15.0f, size);
    const facerig::PhotoLandmarks points = facerig::DetectPhotoLandmarks(detector, shaded);
    const facerig::PhotoFit landmark_fit = facerig::FitPhoto(Setup().model, points.pixels, size, size);
    const facerig::PhotoFit refined = facerig::RefinePhotoFitByShading(Setup().model, shaded, points.pixels, landmark_fit);
    std::printf("%d px photo: shading refinement %.1f ms\n", size, 1e3 * (refined.seconds - landmark_fit.seconds));
  }
}

// The shading term's weight, blur and camera, on training identities (seeds
// 2001 and 99): the weight hardly matters from 0.03 to 0.3, the least blur
// and a refined camera are best.
TEST_CASE("Photo shading fit sweep (shared data)", "[.tune_shading][photo_fit][shared-data]") {
  const auto measure = [](const facerig::PhotoFitParams& params) {
    for (const float yaw : {0.0f, 15.0f}) {
      MeasureFits(8, yaw, 2001, params);
      MeasureFits(8, yaw, 99, params);
    }
  };
  facerig::PhotoFitParams without;
  without.shading = false;
  std::printf("without\n");
  measure(without);
  for (const bool camera : {false, true}) {
    for (const double weight : {0.03, 0.1, 0.3}) {
      for (const float blur : {0.05f, 0.15f}) {
        facerig::PhotoFitParams params;
        params.shading = true;
        params.shading_params.weight = weight;
        params.shading_params.blur_edges = blur;
        params.shading_params.camera = camera;
        std::printf("shading weight %.3f blur %.2f camera %d\n", weight, double(blur), int(camera));
        measure(params);
      }
    }
  }
  facerig::PhotoFitParams more;
  more.shading = true;
  more.shading_params.iterations = 8;
  std::printf("8 iterations\n");
  measure(more);
}

// What a perspective photo costs the fit: the same identities rendered from
// a selfie's, a portrait's and a far distance, framed alike, against the
// orthographic render; dlib's points and the exact projections.
TEST_CASE("Photo fit on perspective renders (shared data)", "[.measure][photo_perspective][shared-data]") {
  facerig::PhotoFitParams orthographic;
  orthographic.camera_distances.clear();
  for (const bool exact : {false, true}) {
    for (const float yaw : {0.0f, 15.0f}) {
      std::printf("%s landmarks:\n", exact ? "exact" : "dlib");
      for (const float distance : {0.0f, 35.0f, 60.0f, 100.0f, 300.0f}) {
        MeasureFits(20, yaw, 1234, orthographic, 0.0f, exact, RenderStyle{.distance_cm = distance});
        std::printf("  perspective:\n");
        MeasureFits(20, yaw, 1234, {}, 0.0f, exact, RenderStyle{.distance_cm = distance});
      }
    }
  }
}

// How many self-calibration rounds, on training identities (seed 2001).
TEST_CASE("Photo fit self-calibration sweep (shared data)", "[.tune_self][photo_fit][shared-data]") {
  for (const int rounds : {0, 1, 2, 3}) {
    facerig::PhotoFitParams params;
    params.self_calibration_rounds = rounds;
    std::printf("self-calibration rounds %d\n", rounds);
    MeasureFits(10, 0.0f, 2001, params);
    MeasureFits(10, 15.0f, 2001, params);
  }
  for (const double sigma : {0.01, 0.02}) {
    facerig::PhotoFitParams params;
    params.landmark_sigma_fraction = sigma;
    std::printf("landmark sigma %.3f\n", sigma);
    MeasureFits(10, 0.0f, 2001, params);
    MeasureFits(10, 15.0f, 2001, params);
  }
}

// How the defaults were chosen (landmark sigma, landmark group weights, jaw contour).
TEST_CASE("Photo fit parameter sweep (shared data)", "[.tune][photo_fit][shared-data]") {
  for (const double sigma : {0.01, 0.015, 0.02, 0.04}) {
    facerig::PhotoFitParams params;
    params.landmark_sigma_fraction = sigma;
    std::printf("sigma %.3f\n", sigma);
    MeasureFits(6, 0.0f, 99, params);
    MeasureFits(6, 15.0f, 99, params);
  }
  for (const float jaw : {0.25f, 0.5f, 1.0f}) {
    for (const float cosine : {0.2f, 0.35f, 0.5f}) {
      facerig::PhotoFitParams params;
        params.jaw_weight = jaw;
      params.silhouette_cosine = cosine;
      std::printf("jaw %.2f silhouette cosine %.2f\n", jaw, cosine);
      MeasureFits(6, 0.0f, 99, params);
      MeasureFits(6, 15.0f, 99, params);
    }
  }
  for (const float brow : {0.2f, 0.5f, 1.0f}) {
    for (const float eye : {0.1f, 0.3f, 1.0f}) {
      facerig::PhotoFitParams params;
        params.brow_weight = brow;
      params.eye_weight = eye;
      std::printf("brow %.2f eye %.2f\n", brow, eye);
      MeasureFits(6, 0.0f, 99, params);
      MeasureFits(6, 15.0f, 99, params);
    }
  }
}

// dlib's remaining bias and its scatter per landmark against the true
// landmark vertices' projections (after the model's offsets), on renders of
// training identities; jaw points but the chin's follow the silhouette, not
// their vertex: left out. A learned table of these (bias removed, 1/sigma^2
// weights) did not beat the group weights on held-out faces.
TEST_CASE("Photo landmark noise on training identities (shared data)", "[.tune_noise][shared-data]") {
  const IctPhotoSetup& setup = Setup();
  facerig::LandmarkDetector& detector = Detector();
  std::vector<glm::dvec2> sum(68, glm::dvec2(0.0)), sum_sq(68, glm::dvec2(0.0));
  int samples = 0;
  for (std::uint64_t seed = 1001; seed <= 1012; ++seed) {
    Pcg32 rng(seed);
    for (const float yaw : {0.0f, 8.0f, 15.0f, -15.0f}) {
      std::vector<double> weights(setup.model.identity_modes.size());
      for (double& w : weights) w = rng.NextNormal();
      const std::vector<glm::vec3> truth = FaceWithWeights(setup.model, weights);
      const RgbImage photo = RenderFace(setup.info, truth, yaw, 512);
      const std::vector<glm::vec2> detected = facerig::DetectPhotoLandmarks(detector, photo).pixels;
      const facerig::RasterView view = facerig::RasterView::Orbit(truth[setup.info.landmark_vertices[30]], 16.0f,
                                                                  512, 512, yaw * kPi / 180.0f);
      glm::vec2 low(1e9f), high(-1e9f);
      for (const glm::vec2 p : detected) {
        low = glm::min(low, p);
        high = glm::max(high, p);
      }
      const float size = std::max(high.x - low.x, high.y - low.y);
      for (std::size_t k = 0; k < 68; ++k) {
        const glm::vec2 v(facerig::ProjectToImage(view, truth[setup.info.landmark_vertices[k]]));
        const glm::dvec2 d((v - detected[k]) / size - setup.model.landmark_offsets[k]);
        sum[k] += d;
        sum_sq[k] += d * d;
      }
      ++samples;
    }
  }
  for (std::size_t k = 0; k < 68; ++k) {
    const glm::dvec2 mean = sum[k] / double(samples);
    const glm::dvec2 sigma = glm::sqrt(glm::max(sum_sq[k] / double(samples) - mean * mean, glm::dvec2(0.0)));
    std::printf("%2zu bias (%+.4f %+.4f) sigma (%.4f %.4f)\n", k, mean.x, mean.y, sigma.x, sigma.y);
  }
}


// The refinement on a real photograph (python3-skimage's astronaut.png), for
// looking at: the fitted faces rendered over the photo before and after, and
// how far the refinement moved the rest face.
TEST_CASE("Photo shading fit on a real photograph (shared data)", "[.measure_real][shared-data]") {
  const IctPhotoSetup& setup = Setup();
  const RgbImage photo = facerig::ReadPhoto(std::filesystem::path(FACERIG_SAMPLE_PHOTOS_DIR) / "astronaut.png").image;
  const facerig::PhotoLandmarks landmarks = facerig::DetectPhotoLandmarks(Detector(), photo);
  const facerig::PhotoFit fit = facerig::FitPhoto(setup.model, landmarks.pixels, photo.width, photo.height);
  const facerig::PhotoFit refined = facerig::RefinePhotoFitByShading(setup.model, photo, landmarks.pixels, fit);
  for (const auto& [name, f] : {std::pair("before", &fit), std::pair("after", &refined)}) {
    facerig::Mesh mesh{.positions = f->posed_positions, .triangles = setup.model.visible_triangles};
    const facerig::RasterBuffers buffers = facerig::Rasterize(mesh, f->view);
    const RgbImage render = facerig::Shade(buffers, mesh, {}, f->view);
    RgbImage overlay = photo;
    for (std::size_t i = 0; i < buffers.triangle_ids.size(); ++i) {
      if (buffers.triangle_ids[i] == facerig::kNoTriangle || (i / std::size_t(photo.width) + i) % 2 == 0) continue;
      for (int c = 0; c < 3; ++c) overlay.pixels[3 * i + std::size_t(c)] = render.pixels[3 * i + std::size_t(c)];
    }
    facerig::WritePng(facerig::test::OutputPath(std::string("photo_shading_real_") + name + ".png"), overlay);
  }
  const facerig::VertexRange face = setup.info.Group("face");
  std::printf("astronaut: landmark residual %.2f -> %.2f px, rest face moved %.2f mm, %.1f ms\n", fit.rms_pixels,
              refined.rms_pixels, FaceErrorMm(refined.rest_positions, fit.rest_positions, face),
              1e3 * (refined.seconds - fit.seconds));
  // How much the answer depends on the term's settings: on renders they hardly matter.
  for (const auto& [weight, blur] : {std::pair(0.01, 0.05f), std::pair(0.1, 0.05f), std::pair(0.03, 0.15f),
                                     std::pair(0.03, 0.3f)}) {
    facerig::PhotoFitParams params;
    params.shading_params.weight = weight;
    params.shading_params.blur_edges = blur;
    const facerig::PhotoFit other = facerig::RefinePhotoFitByShading(setup.model, photo, landmarks.pixels, fit, params);
    std::printf("  weight %.2f blur %.2f: moved %.2f mm from the landmark fit, %.2f mm from the default refinement\n",
                weight, double(blur), FaceErrorMm(other.rest_positions, fit.rest_positions, face),
                FaceErrorMm(other.rest_positions, refined.rest_positions, face));
  }
}

// The measurement's render styles, written for looking at.
TEST_CASE("Photo fit render styles (shared data)", "[.look_styles][shared-data]") {
  const std::vector<glm::vec3>& face = Setup().model.neutral;
  for (const auto& [name, style] : {std::pair("flat", RenderStyle{}), std::pair("side_light", SideLight()),
                                    std::pair("blotchy", Blotchy()), std::pair("hard", Hard())}) {
    facerig::WritePng(facerig::test::OutputPath(std::string("photo_fit_style_") + name + ".png"),
                      RenderFace(Setup().info, face, 15.0f, 512, style));
  }
}

// Real photographs have no true shape to compare with; dlib's nose points
// (27..35) held out of the fit are one: how far the fitted nose vertices
// project from them (after dlib's offsets), fractions of the face size, with
// and without the shading term, on dlib's example photos and the astronaut.
TEST_CASE("Photo shading fit predicts held-out nose points on real photographs (shared data)",
          "[.measure_real][shared-data]") {
  const IctPhotoSetup& setup = Setup();
  std::vector<std::filesystem::path> paths{std::filesystem::path(FACERIG_SAMPLE_PHOTOS_DIR) / "astronaut.png"};
  for (const auto& entry : std::filesystem::directory_iterator("/usr/share/doc/libdlib19.1/examples/faces")) {
    if (entry.path().extension() == ".jpg") paths.push_back(entry.path());
  }
  std::sort(paths.begin(), paths.end());
  facerig::PhotoFitParams held_out;
  held_out.nose_weight = 0.0f;
  double sum_without = 0.0, sum_with = 0.0;
  int count = 0;
  for (const std::filesystem::path& path : paths) {
    const RgbImage photo = facerig::ReadPhoto(path).image;
    facerig::PhotoLandmarks landmarks;
    try {
      landmarks = facerig::DetectPhotoLandmarks(Detector(), photo);
    } catch (const facerig::LandmarkDetectionError&) {
      continue;
    }
    const facerig::PhotoFit fit = facerig::FitPhoto(setup.model, landmarks.pixels, photo.width, photo.height, held_out);
    const facerig::PhotoFit refined =
        facerig::RefinePhotoFitByShading(setup.model, photo, landmarks.pixels, fit, held_out);
    const auto nose_error = [&](const facerig::PhotoFit& f) {
      double squared = 0.0;
      for (std::size_t k = 27; k <= 35; ++k) {
        const glm::vec2 d = f.model_pixels[k] - f.target_pixels[k];
        squared += glm::dot(d, d);
      }
      return std::sqrt(squared / 9.0) / std::max(landmarks.box.width(), landmarks.box.height());
    };
    const double without = nose_error(fit), with = nose_error(refined);
    std::printf("%-28s face %4d px: held-out nose points %.4f -> %.4f of the face\n", path.filename().c_str(),
                std::max(landmarks.box.width(), landmarks.box.height()), without, with);
    sum_without += without;
    sum_with += with;
    ++count;
  }
  std::printf("mean over %d photos: %.4f without, %.4f with the shading term\n", count, sum_without / count,
              sum_with / count);
}
