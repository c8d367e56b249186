// Fitting the ICT-FaceKit model to one picture: random identities rendered by
// the project's rasterizer, landmarks by dlib, the fit compared with the truth.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <glm/geometric.hpp>

#include "facerig/offline/error.h"
#include "facerig/offline/photo_fit.h"
#include "facerig/offline/similarity.h"
#include "facerig/runtime/behaviour/blink.h"
#include "facerig/runtime/rig_builder.h"
#include "support/registration_targets.h"
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

const IctPhotoSetup& Setup() {
  static const IctPhotoSetup setup = [] {
    IctPhotoSetup s;
    s.info = facerig::test::LoadIctTemplateInfo(facerig::test::IctRig());
    s.model = facerig::BuildPhotoFaceModel(facerig::test::IctRig(), s.info, facerig::test::IctFaces().identities);
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

// The head rendered with a flat skin colour and Lambert light; the eye films (transparent in ICT) left out.
RgbImage RenderFace(const facerig::FaceTemplateInfo& info, const std::vector<glm::vec3>& positions, float yaw_degrees,
                    int size) {
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
  }
  std::vector<glm::vec3> normals(positions.size());
  facerig::ComputeVertexNormals(positions, mesh.triangles, normals);
  for (const facerig::Triangle& t : mesh.triangles) {
    for (const std::uint32_t v : t) mesh.corner_normals.push_back(normals[v]);
  }
  const glm::vec3 nose = positions[info.landmark_vertices[30]];
  const facerig::RasterView view =
      facerig::RasterView::Orbit(nose, 16.0f, size, size, yaw_degrees * kPi / 180.0f);
  return facerig::Shade(facerig::Rasterize(mesh, view), mesh, albedo, view);
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

struct Errors {
  double fit = 0.0, mean_face = 0.0, best = 0.0, fit_seconds = 0.0;
  int count = 0;
};

Errors MeasureFits(int faces, float yaw_degrees, std::uint64_t seed, const facerig::PhotoFitParams& params = {}) {
  const IctPhotoSetup& setup = Setup();
  const facerig::VertexRange face = setup.info.Group("face");
  facerig::LandmarkDetector detector;
  Pcg32 rng(seed);
  Errors errors;
  for (int f = 0; f < faces; ++f) {
    std::vector<double> weights(setup.model.identity_modes.size());
    for (double& w : weights) w = rng.NextNormal();
    const std::vector<glm::vec3> truth = FaceWithWeights(setup.model, weights);
    const RgbImage photo = RenderFace(setup.info, truth, yaw_degrees, 512);
    const facerig::PhotoLandmarks landmarks = facerig::DetectPhotoLandmarks(detector, photo);
    const facerig::PhotoFit fit = facerig::FitPhoto(setup.model, landmarks.pixels, photo.width, photo.height, params);
    if (f == 0) {
      facerig::WritePhotoFitPng(facerig::test::OutputPath("photo_fit_yaw" + std::to_string(int(yaw_degrees)) + ".png"),
                                photo, landmarks, fit);
    }
    errors.fit += FaceErrorMm(fit.rest_positions, truth, face);
    errors.mean_face += FaceErrorMm(setup.model.neutral, truth, face);
    errors.best += FaceErrorMm(ProjectOnModes(setup.model, truth, face), truth, face);
    errors.fit_seconds = std::max(errors.fit_seconds, fit.seconds);
    ++errors.count;
  }
  errors.fit /= faces;
  errors.mean_face /= faces;
  errors.best /= faces;
  std::printf("photo fit, yaw %2.0f, %d faces: fit %.2f mm, mean face %.2f mm, best %.3f mm; slowest fit %.1f ms\n",
              double(yaw_degrees), faces, errors.fit, errors.mean_face, errors.best, 1e3 * errors.fit_seconds);
  return errors;
}

}  // namespace

TEST_CASE("Photo fit recovers random ICT identities from renders (shared data)", "[photo_fit][shared-data]") {
  for (const float yaw : {0.0f, 15.0f}) {
    const Errors e = MeasureFits(2, yaw, 17);
    CHECK(e.best < 0.05);
    CHECK(e.fit < 0.5 * e.mean_face);
    CHECK(e.fit_seconds < 0.5);
  }
}

TEST_CASE("Photo fit accuracy over many faces (shared data)", "[.measure][photo_fit][shared-data]") {
  for (const float yaw : {0.0f, 15.0f}) MeasureFits(12, yaw, 1234);
}
