// The shape half of the photo fit: identity and expression weights by
// regularised linear least squares against the landmarks (camera fixed), the
// jaw line re-matched to the model's contour, alternating with the camera.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Dense>
#include <glm/geometric.hpp>

#include "facerig/offline/landmarks/dlib68.h"
#include "facerig/offline/error.h"
#include "facerig/offline/photo/fit.h"
#include "facerig/offline/geometry/stats.h"
#include "facerig/runtime/rig_builder.h"
#include "photo/fit/shape_system.h"
#include "geometry/bounding_box.h"

namespace facerig {

namespace photo_shape {

const std::vector<glm::vec3>& Mode(const PhotoFaceModel& model, std::size_t i) {
  const std::size_t identities = model.identity_modes.size();
  return i < identities ? model.identity_modes[i] : model.expression_deltas[i - identities];
}

double PriorPrecision(const PhotoFaceModel& model, const PhotoFitParams& params, std::size_t i) {
  return i < model.identity_modes.size() ? 1.0 : 1.0 / (params.expression_sigma * params.expression_sigma);
}

std::vector<glm::vec3> ShapeOf(const PhotoFaceModel& model, const Eigen::VectorXd& weights, std::size_t first,
                               std::size_t count, std::size_t mode_count) {
  std::vector<glm::vec3> shape(model.neutral.begin() + static_cast<std::ptrdiff_t>(first),
                               model.neutral.begin() + static_cast<std::ptrdiff_t>(first + count));
  for (std::size_t i = 0; i < mode_count; ++i) {
    const float w = static_cast<float>(weights[static_cast<Eigen::Index>(i)]);
    if (w == 0.0f) continue;
    const std::vector<glm::vec3>& mode = Mode(model, i);
    for (std::size_t v = 0; v < count; ++v) shape[v] += w * mode[first + v];
  }
  return shape;
}

glm::vec3 Centroid(std::span<const glm::vec3> points) {
  glm::vec3 sum(0.0f);
  for (const glm::vec3 p : points) sum += p;
  return sum / static_cast<float>(std::max<std::size_t>(1, points.size()));
}

}  // namespace photo_shape

using photo_shape::BuildSystem;
using photo_shape::FaceSize;
using photo_shape::FillResult;
using photo_shape::LandmarkPrecisions;
using photo_shape::LinearSystem;
using photo_shape::Mode;
using photo_shape::PriorPrecision;
using photo_shape::ShapeOf;
using photo_shape::SolveBounded;

namespace {

constexpr std::size_t kJawCount = 17;
constexpr std::size_t kChinFirst = 7;
constexpr std::size_t kChinLast = 9;
// Expression weights are clamped to [0, 1] by re-solving with the clamped ones fixed.
constexpr int kClampPasses = 3;

void CheckInput(std::span<const glm::vec2> landmarks, int width, int height) {
  if (landmarks.size() != kDlibLandmarkCount) {
    throw InvalidInputError("photo fit: expected 68 landmarks, got " + std::to_string(landmarks.size()), "landmarks");
  }
  if (width <= 0 || height <= 0) throw InvalidInputError("photo fit: the image size must be positive", "image size");
  for (const glm::vec2 p : landmarks) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
      throw InvalidInputError("photo fit: a landmark is not finite", "landmarks");
    }
  }
}

glm::vec3 ShapeAt(const PhotoFaceModel& model, const Eigen::VectorXd& weights, std::uint32_t v) {
  glm::vec3 p = model.neutral[v];
  for (std::size_t i = 0; i < model.unknown_count(); ++i) {
    if (weights[static_cast<Eigen::Index>(i)] != 0.0) p += static_cast<float>(weights[static_cast<Eigen::Index>(i)]) * Mode(model, i)[v];
  }
  return p;
}


// For each jaw landmark but the chin's, the contour candidate on the current
// silhouette (on the landmark's side of the face) nearest to it in the image;
// the template's own vertex stays when none is nearer.
void ChooseContourVertices(const PhotoFaceModel& model, const Eigen::VectorXd& weights, const ScaledOrthoCamera& camera,
                           std::span<const glm::vec2> landmarks, int width, int height, float silhouette_cosine,
                           std::vector<std::uint32_t>& vertices) {
  const std::size_t count = static_cast<std::size_t>(model.region.last) + 1;
  const std::vector<glm::vec3> shape = ShapeOf(model, weights, 0, count, model.unknown_count());
  std::vector<glm::vec3> normals(count);
  ComputeVertexNormals(shape, model.region_triangles, normals);
  const glm::vec3 right(camera.rotation[0][0], camera.rotation[1][0], camera.rotation[2][0]);
  const glm::vec3 forward(camera.rotation[0][2], camera.rotation[1][2], camera.rotation[2][2]);
  for (std::size_t k = 0; k < kJawCount; ++k) {
    if (k >= kChinFirst && k <= kChinLast) continue;
    const float side = k < kChinFirst ? -1.0f : 1.0f;  // image left: the normal points left
    const std::uint32_t fixed = model.landmark_vertices[k];
    float best = glm::length(ProjectPixel(camera, shape[fixed], width, height) - landmarks[k]);
    vertices[k] = fixed;
    for (const std::uint32_t v : model.contour_candidates) {
      if (std::abs(glm::dot(normals[v], forward)) > silhouette_cosine || side * glm::dot(normals[v], right) <= 0.0f) {
        continue;
      }
      const float d = glm::length(ProjectPixel(camera, shape[v], width, height) - landmarks[k]);
      if (d < best) {
        best = d;
        vertices[k] = v;
      }
    }
  }
}

bool OnContour(std::size_t k, const PhotoFitParams& params) {
  return params.moving_contour && k < kJawCount && (k < kChinFirst || k > kChinLast);
}

}  // namespace

namespace photo_shape {

LinearSystem BuildSystem(const PhotoFaceModel& model, const ScaledOrthoCamera& camera,
                         std::span<const glm::vec2> landmarks, std::span<const std::uint32_t> vertices,
                         std::span<const glm::vec2> precisions, int width, int height, const PhotoFitParams& params) {
  const auto n = static_cast<Eigen::Index>(model.unknown_count());
  LinearSystem system{Eigen::MatrixXd::Zero(n, n), Eigen::VectorXd::Zero(n)};
  const glm::vec3 right(camera.rotation[0][0], camera.rotation[1][0], camera.rotation[2][0]);
  const glm::vec3 up(camera.rotation[0][1], camera.rotation[1][1], camera.rotation[2][1]);
  Eigen::Matrix2Xd jacobian(2, n);
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    const std::uint32_t v = vertices[k];
    for (Eigen::Index i = 0; i < n; ++i) {
      const glm::vec3 d = Mode(model, static_cast<std::size_t>(i))[v];
      jacobian(0, i) = camera.scale * glm::dot(right, d);
      jacobian(1, i) = -camera.scale * glm::dot(up, d);
    }
    const glm::vec2 r = landmarks[k] - ProjectPixel(camera, model.neutral[v], width, height);
    const Eigen::Matrix2d w = Eigen::Vector2d(precisions[k].x, precisions[k].y).asDiagonal();
    system.normal += jacobian.transpose() * w * jacobian;
    system.rhs += jacobian.transpose() * w * Eigen::Vector2d(r.x, r.y);
  }
  for (Eigen::Index i = 0; i < n; ++i) system.normal(i, i) += PriorPrecision(model, params, static_cast<std::size_t>(i));
  return system;
}

// Solves with the expression weights kept in [0, 1]: out-of-range ones are
// fixed at the bound and the rest re-solved.
Eigen::VectorXd SolveBounded(const LinearSystem& system, std::size_t identity_count) {
  const Eigen::Index n = system.rhs.size();
  std::vector<int> fixed(static_cast<std::size_t>(n), -1);  // -1 free, else the bound (0 or 1)
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  for (int pass = 0; pass <= kClampPasses; ++pass) {
    Eigen::MatrixXd a = system.normal;
    Eigen::VectorXd b = system.rhs;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (fixed[static_cast<std::size_t>(i)] < 0) continue;
      const double value = fixed[static_cast<std::size_t>(i)];
      b -= a.col(i) * value;
      a.row(i).setZero();
      a.col(i).setZero();
      a(i, i) = 1.0;
      b[i] = value;
    }
    x = a.ldlt().solve(b);
    bool changed = false;
    for (Eigen::Index i = static_cast<Eigen::Index>(identity_count); i < n; ++i) {
      if (fixed[static_cast<std::size_t>(i)] >= 0 || (x[i] >= 0.0 && x[i] <= 1.0)) continue;
      fixed[static_cast<std::size_t>(i)] = x[i] < 0.0 ? 0 : 1;
      changed = true;
    }
    if (!changed) break;
  }
  for (Eigen::Index i = static_cast<Eigen::Index>(identity_count); i < n; ++i) x[i] = std::clamp(x[i], 0.0, 1.0);
  return x;
}

}  // namespace photo_shape

namespace {

std::vector<float> GroupWeights(const PhotoFitParams& params) {
  std::vector<float> weights(kDlibLandmarkCount, 1.0f);
  for (std::size_t k = 0; k < kJawCount; ++k) weights[k] = params.jaw_weight;
  for (std::size_t k = 17; k <= 26; ++k) weights[k] = params.brow_weight;
  for (std::size_t k = dlib68::kRightEyeFirst; k <= dlib68::kLeftEyeLast; ++k) weights[k] = params.eye_weight;
  for (std::size_t k = 27; k <= 35; ++k) weights[k] = params.nose_weight;
  return weights;
}

}  // namespace

std::vector<glm::vec2> photo_shape::LandmarkPrecisions(const PhotoFitParams& params, double face_size) {
  const std::vector<float> weights = GroupWeights(params);
  const double sigma = params.landmark_sigma_fraction * face_size;
  std::vector<glm::vec2> precisions;
  for (const float w : weights) precisions.emplace_back(static_cast<float>(w / (sigma * sigma)));
  return precisions;
}

namespace {

// The camera takes one weight per point: the mean of its two axes' precisions.
std::vector<float> CameraWeights(std::span<const glm::vec2> precisions) {
  std::vector<float> weights;
  for (const glm::vec2 p : precisions) weights.push_back(0.5f * (p.x + p.y));
  return weights;
}

// The detected points moved by the model's offsets: where the landmark
// vertices would project.
std::vector<glm::vec2> CorrectedLandmarks(const PhotoFaceModel& model, std::span<const glm::vec2> detected,
                                          double face_size, const PhotoFitParams& params) {
  std::vector<glm::vec2> landmarks(detected.begin(), detected.end());
  const bool offsets = params.remove_landmark_offsets && model.landmark_offsets.size() == landmarks.size();
  for (std::size_t k = 0; k < landmarks.size(); ++k) {
    if (offsets && !OnContour(k, params)) landmarks[k] += static_cast<float>(face_size) * model.landmark_offsets[k];
  }
  return landmarks;
}

}  // namespace

double photo_shape::FaceSize(std::span<const glm::vec2> landmarks) {
  const glm::vec2 extent = BoxAround(landmarks).extent();
  return std::max(1.0f, std::max(extent.x, extent.y));
}

namespace {

std::vector<glm::vec3> PointsAt(const PhotoFaceModel& model, const Eigen::VectorXd& weights,
                                std::span<const std::uint32_t> vertices) {
  std::vector<glm::vec3> points;
  for (const std::uint32_t v : vertices) points.push_back(ShapeAt(model, weights, v));
  return points;
}

void RefreshProjection(std::span<const glm::vec2> landmarks, int width, int height, PhotoFit& fit);

// dlib's points above and below the lips' and the eyes' openings, paired
// across each opening; and the other points of the lips' upper and lower halves.
struct Opening {
  std::vector<std::array<int, 2>> pairs;  // (upper, lower) across the opening
  std::vector<int> upper, lower;          // every point that moves with each side
};
const std::array<Opening, 3>& Openings() {
  static const std::array<Opening, 3> openings{
      Opening{{{61, 67}, {62, 66}, {63, 65}}, {61, 62, 63, 50, 51, 52}, {65, 66, 67, 56, 57, 58}},
      Opening{{{37, 41}, {38, 40}}, {37, 38}, {40, 41}},
      Opening{{{43, 47}, {44, 46}}, {43, 44}, {46, 47}}};
  return openings;
}

// The landmarks with each opening brought back to the model's (posed)
// opening, each side moving half: how far the mouth and eyes are open is an
// expression, not the face's shape, so the rest face keeps the template's.
std::vector<glm::vec2> OpeningsAsModelled(std::span<const glm::vec2> landmarks, std::span<const glm::vec3> posed,
                                          std::span<const std::uint32_t> vertices, const ScaledOrthoCamera& camera,
                                          int width, int height) {
  std::vector<glm::vec2> kept(landmarks.begin(), landmarks.end());
  const auto excess = [&](int k) { return landmarks[k] - ProjectPixel(camera, posed[vertices[k]], width, height); };
  for (const Opening& opening : Openings()) {
    glm::vec2 wider(0.0f);  // how much more the photo's opening is open than the model's
    for (const auto& [upper, lower] : opening.pairs) wider += excess(lower) - excess(upper);
    wider /= static_cast<float>(opening.pairs.size());
    for (const int k : opening.upper) kept[k] += 0.5f * wider;
    for (const int k : opening.lower) kept[k] -= 0.5f * wider;
  }
  return kept;
}

}  // namespace

void photo_shape::FillResult(const PhotoFaceModel& model, const Eigen::VectorXd& weights,
                             std::span<const glm::vec2> landmarks, int width, int height, PhotoFit& fit) {
  fit.identity_weights.clear();
  fit.expression_weights.clear();
  const std::size_t identities = model.identity_modes.size();
  for (std::size_t i = 0; i < model.unknown_count(); ++i) {
    const auto w = static_cast<float>(weights[static_cast<Eigen::Index>(i)]);
    (i < identities ? fit.identity_weights : fit.expression_weights).push_back(w);
  }
  fit.expression_names = model.expression_names;
  fit.rest_positions = ShapeOf(model, weights, 0, model.neutral.size(), identities);
  fit.posed_positions = ShapeOf(model, weights, 0, model.neutral.size(), model.unknown_count());
  RefreshProjection(landmarks, width, height, fit);
}

namespace {

// model_pixels, rms_pixels and the view from the posed positions.
void RefreshProjection(std::span<const glm::vec2> landmarks, int width, int height, PhotoFit& fit) {
  glm::vec3 centre(0.0f);
  for (const std::uint32_t v : fit.landmark_vertices) centre += fit.posed_positions[v];
  centre /= static_cast<float>(fit.landmark_vertices.size());
  fit.view = ToPerspectiveView(fit.camera, width, height, centre, fit.camera_distance);
  fit.model_pixels.clear();
  fit.target_pixels.assign(landmarks.begin(), landmarks.end());
  double squared = 0.0;
  for (std::size_t k = 0; k < landmarks.size(); ++k) {
    const glm::vec3 p = fit.posed_positions[fit.landmark_vertices[k]];
    fit.model_pixels.push_back(fit.camera_distance > 0.0f ? glm::vec2(ProjectToImage(fit.view, p))
                                                          : ProjectPixel(fit.camera, p, width, height));
    const glm::vec2 d = fit.model_pixels.back() - landmarks[k];
    squared += glm::dot(d, d);
  }
  fit.rms_pixels = std::sqrt(squared / static_cast<double>(landmarks.size()));
}

// The camera from the current shape; with a perspective camera `seen`
// becomes the landmarks as the orthographic camera would see them.
void FitCamera(const PhotoFaceModel& model, const Eigen::VectorXd& weights, std::span<const glm::vec2> landmarks,
               std::span<const float> camera_weights, int width, int height, std::vector<glm::vec2>& seen,
               PhotoFit& fit) {
  const std::vector<glm::vec3> points = PointsAt(model, weights, fit.landmark_vertices);
  fit.camera = FitScaledOrthoCamera(points, seen, camera_weights, width, height);
  if (fit.camera_distance <= 0.0f) return;
  seen = OrthographicPixels(landmarks, points, fit.camera, fit.camera_distance, width, height);
  fit.camera = FitScaledOrthoCamera(points, seen, camera_weights, width, height);
}

// Camera and shape in turn from `weights` on; the camera last.
void Alternate(const PhotoFaceModel& model, std::span<const glm::vec2> landmarks, std::span<const glm::vec2> precisions,
               int iterations, int width, int height, const PhotoFitParams& params, Eigen::VectorXd& weights,
               PhotoFit& fit) {
  const std::vector<float> camera_weights = CameraWeights(precisions);
  std::vector<glm::vec2> seen(landmarks.begin(), landmarks.end());
  for (int iteration = 0; iteration < std::max(1, iterations); ++iteration) {
    FitCamera(model, weights, landmarks, camera_weights, width, height, seen, fit);
    if (params.moving_contour) {
      ChooseContourVertices(model, weights, fit.camera, seen, width, height, params.silhouette_cosine,
                            fit.landmark_vertices);
    }
    const LinearSystem system =
        BuildSystem(model, fit.camera, seen, fit.landmark_vertices, precisions, width, height, params);
    weights = SolveBounded(system, model.identity_modes.size());
  }
  FitCamera(model, weights, landmarks, camera_weights, width, height, seen, fit);
}

// What the fit minimises: the landmark residuals in the photo (through the
// perspective view when there is one) over their variances, plus the prior.
double FitObjective(const PhotoFaceModel& model, const Eigen::VectorXd& weights, std::span<const glm::vec2> landmarks,
                    std::span<const glm::vec2> precisions, int width, int height, const PhotoFitParams& params,
                    const PhotoFit& fit) {
  const std::vector<glm::vec3> points = PointsAt(model, weights, fit.landmark_vertices);
  const RasterView view =
      ToPerspectiveView(fit.camera, width, height, photo_shape::Centroid(points), fit.camera_distance);
  double sum = 0.0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const glm::vec2 d = glm::vec2(ProjectToImage(view, points[k])) - landmarks[k];
    sum += precisions[k].x * d.x * d.x + precisions[k].y * d.y * d.y;
  }
  for (Eigen::Index i = 0; i < weights.size(); ++i) {
    sum += PriorPrecision(model, params, static_cast<std::size_t>(i)) * weights[i] * weights[i];
  }
  return sum;
}

// The orthographic fit in `weights` and `fit` replaced by the perspective
// one of params.camera_distances whose FitObjective is lowest, if lower.
void ChooseCameraDistance(const PhotoFaceModel& model, std::span<const glm::vec2> landmarks,
                          std::span<const glm::vec2> precisions, int width, int height, const PhotoFitParams& params,
                          Eigen::VectorXd& weights, PhotoFit& fit) {
  double best = FitObjective(model, weights, landmarks, precisions, width, height, params, fit);
  for (const float distance : params.camera_distances) {
    if (!(distance > 0.0f) || distance == fit.camera_distance) continue;
    Eigen::VectorXd trial_weights = Eigen::VectorXd::Zero(weights.size());
    PhotoFit trial;
    trial.landmark_vertices = model.landmark_vertices;
    trial.camera_distance = distance;
    Alternate(model, landmarks, precisions, params.iterations, width, height, params, trial_weights, trial);
    const double objective = FitObjective(model, trial_weights, landmarks, precisions, width, height, params, trial);
    if (objective < best) {
      best = objective;
      weights = trial_weights;
      fit = std::move(trial);
    }
  }
}

// The photo's camera as a view of at most kSelfCalibrationSize pixels (dlib's
// offsets are in fractions of the face, so the size does not change them).
constexpr int kSelfCalibrationSize = 512;

RasterView SelfCalibrationView(const PhotoFaceModel& model, const Eigen::VectorXd& weights, const PhotoFit& fit,
                               int width, int height) {
  glm::vec3 centre(0.0f);
  for (const std::uint32_t v : fit.landmark_vertices) centre += ShapeAt(model, weights, v);
  RasterView view = ToPerspectiveView(fit.camera, width, height,
                                      centre / static_cast<float>(fit.landmark_vertices.size()), fit.camera_distance);
  const float shrink =
      std::min(1.0f, static_cast<float>(kSelfCalibrationSize) / static_cast<float>(std::max(width, height)));
  view.width = std::max(1, static_cast<int>(std::lround(static_cast<float>(width) * shrink)));
  view.height = std::max(1, static_cast<int>(std::lround(static_cast<float>(height) * shrink)));
  return view;
}

// dlib's offsets on a render of the fit so far in place of the neutral's, then
// a re-fit: dlib's error depends on the face, and the fit is nearer the photo's
// face than the neutral is. A render dlib finds no face on ends the rounds.
void SelfCalibrate(const PhotoFaceModel& model, std::span<const glm::vec2> detected,
                   std::span<const glm::vec2> precisions, int width, int height, const PhotoFitParams& params,
                   std::vector<glm::vec2>& landmarks, Eigen::VectorXd& weights, PhotoFit& fit) {
  const double face_size = FaceSize(detected);
  for (int round = 0; round < params.self_calibration_rounds; ++round) {
    const std::vector<glm::vec3> posed = ShapeOf(model, weights, 0, model.neutral.size(), model.unknown_count());
    std::vector<glm::vec2> offsets;
    try {
      const RasterView view = SelfCalibrationView(model, weights, fit, width, height);
      offsets = MeasureDlibOffsets(model, posed, view, *model.detector);
    } catch (const LandmarkDetectionError&) {
      return;
    }
    landmarks.assign(detected.begin(), detected.end());
    for (std::size_t k = 0; k < landmarks.size(); ++k) {
      if (OnContour(k, params)) continue;
      landmarks[k] += static_cast<float>(face_size) * offsets[k];
    }
    Alternate(model, landmarks, precisions, params.iterations, width, height, params, weights, fit);
  }
}

}  // namespace

PhotoFit FitPhoto(const PhotoFaceModel& model, std::span<const glm::vec2> detected, int width, int height,
                  const PhotoFitParams& params) {
  const auto start = std::chrono::steady_clock::now();
  CheckInput(detected, width, height);
  const double face_size = FaceSize(detected);
  const std::vector<glm::vec2> precisions = LandmarkPrecisions(params, face_size);
  std::vector<glm::vec2> landmarks = CorrectedLandmarks(model, detected, face_size, params);
  Eigen::VectorXd weights = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(model.unknown_count()));
  PhotoFit fit;
  fit.landmark_vertices = model.landmark_vertices;
  Alternate(model, landmarks, precisions, params.iterations, width, height, params, weights, fit);
  if (!model.identity_modes.empty()) {
    ChooseCameraDistance(model, landmarks, precisions, width, height, params, weights, fit);
  }
  if (model.detector != nullptr && !model.identity_modes.empty() && params.remove_landmark_offsets) {
    SelfCalibrate(model, detected, precisions, width, height, params, landmarks, weights, fit);
  }
  if (params.deform_without_identity && model.identity_modes.empty()) {
    // Expressions stay as fitted: the deformation moves rest and posed alike.
    // The posed face matches the photo (what the texture is baked from); the
    // rest face takes the deformation with the openings as modelled.
    std::vector<glm::vec3> posed = ShapeOf(model, weights, 0, model.neutral.size(), model.unknown_count());
    std::vector<glm::vec3> shaped = posed;
    const std::vector<glm::vec3> before = posed;
    const std::vector<glm::vec2> closed =
        OpeningsAsModelled(landmarks, before, fit.landmark_vertices, fit.camera, width, height);
    RbfDeformToLandmarks(posed, fit.landmark_vertices, landmarks, fit.camera, width, height);
    RbfDeformToLandmarks(shaped, fit.landmark_vertices, closed, fit.camera, width, height);
    FillResult(model, weights, landmarks, width, height, fit);
    for (std::size_t v = 0; v < posed.size(); ++v) fit.rest_positions[v] += shaped[v] - before[v];
    fit.posed_positions = std::move(posed);
    fit.deformed = true;
    RefreshProjection(landmarks, width, height, fit);
  } else {
    FillResult(model, weights, landmarks, width, height, fit);
  }
  fit.seconds = SecondsSince(start);
  return fit;
}

}  // namespace facerig
