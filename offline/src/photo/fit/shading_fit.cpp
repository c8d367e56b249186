// The photo fit refined by the photo's shading (analysis by synthesis, as in
// Blanz & Vetter's morphable model fits): Gauss-Newton on the landmark term
// and prior plus the colour at visible face-skin vertices against spherical-
// harmonic lighting of their normals.
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "facerig/offline/error.h"
#include "facerig/offline/landmarks/dlib68.h"
#include "facerig/offline/photo/fit.h"
#include "facerig/offline/photo/texture.h"
#include "facerig/offline/geometry/stats.h"
#include "facerig/runtime/rig_builder.h"
#include "photo/face_outline.h"
#include "photo/fit/shape_system.h"
#include "geometry/bounding_box.h"

namespace facerig {

namespace {

constexpr int kHarmonics = 9;
// Huber's threshold in robust standard deviations (95 % efficiency on Gaussian noise).
constexpr double kHuber = 1.345;
// The pixel noise is never taken below one 8-bit step.
constexpr double kMinNoise = 1.0 / 255.0;

// The second-order spherical harmonics of a unit normal, unnormalised (the
// lighting absorbs each constant), and their gradients in the normal.
void Harmonics(glm::vec3 n, std::array<float, kHarmonics>& y, std::array<glm::vec3, kHarmonics>& dy) {
  y = {1.0f, n.x, n.y, n.z, n.x * n.y, n.x * n.z, n.y * n.z, n.x * n.x - n.y * n.y, 3.0f * n.z * n.z - 1.0f};
  dy = {glm::vec3(0.0f),
        glm::vec3(1.0f, 0.0f, 0.0f),
        glm::vec3(0.0f, 1.0f, 0.0f),
        glm::vec3(0.0f, 0.0f, 1.0f),
        glm::vec3(n.y, n.x, 0.0f),
        glm::vec3(n.z, 0.0f, n.x),
        glm::vec3(0.0f, n.z, n.y),
        glm::vec3(2.0f * n.x, -2.0f * n.y, 0.0f),
        glm::vec3(0.0f, 0.0f, 6.0f * n.z)};
}

// The photo's window round the face, blurred, in [0, 1].
struct BlurredWindow {
  cv::Rect window;
  cv::Mat colour;  // CV_32FC3

  glm::vec3 At(float u, float v) const {
    const int x = static_cast<int>(u), y = static_cast<int>(v);
    const float fx = u - static_cast<float>(x), fy = v - static_cast<float>(y);
    const auto texel = [&](int xx, int yy) {
      const cv::Vec3f c = colour.at<cv::Vec3f>(yy, xx);
      return glm::vec3(c[0], c[1], c[2]);
    };
    return (1.0f - fy) * ((1.0f - fx) * texel(x, y) + fx * texel(x + 1, y)) +
           fy * ((1.0f - fx) * texel(x, y + 1) + fx * texel(x + 1, y + 1));
  }
  // Colour and its gradient (central differences of the bilinear samples) at
  // a photo position (pixel centres at +0.5); false too near the window's edge.
  bool Sample(glm::vec2 p, glm::vec3& value, glm::vec3& dx, glm::vec3& dy) const {
    const float u = p.x - 0.5f - static_cast<float>(window.x), v = p.y - 0.5f - static_cast<float>(window.y);
    if (!(u >= 1.0f && v >= 1.0f && u < static_cast<float>(colour.cols - 2) &&
          v < static_cast<float>(colour.rows - 2))) {
      return false;
    }
    value = At(u, v);
    dx = 0.5f * (At(u + 1.0f, v) - At(u - 1.0f, v));
    dy = 0.5f * (At(u, v + 1.0f) - At(u, v - 1.0f));
    return true;
  }
};

BlurredWindow BlurPhoto(const RgbImage& photo, cv::Rect window, double sigma) {
  const cv::Mat rgb(photo.height, photo.width, CV_8UC3, const_cast<std::uint8_t*>(photo.pixels.data()));
  BlurredWindow blurred{window, {}};
  rgb(window).convertTo(blurred.colour, CV_32FC3, 1.0 / 255.0);
  cv::GaussianBlur(blurred.colour, blurred.colour, cv::Size(0, 0), sigma);
  return blurred;
}

// Pixels relative to origin.
std::vector<cv::Point> ToPoints(std::span<const glm::vec2> pixels, cv::Point origin) {
  std::vector<cv::Point> points;
  for (const glm::vec2 p : pixels) {
    points.emplace_back(static_cast<int>(std::lround(p.x)) - origin.x, static_cast<int>(std::lround(p.y)) - origin.y);
  }
  return points;
}

// Landmarks first..last (dlib68 numbers) as a polygon relative to origin.
std::vector<cv::Point> Polygon(std::span<const glm::vec2> landmarks, std::size_t first, std::size_t last,
                               cv::Point origin) {
  return ToPoints(landmarks.subspan(first, last - first + 1), origin);
}

// 255 where the photo shows the face's skin by dlib's points: inside the jaw
// line and the brows lifted to the forehead, shrunk by `margin`, without the
// eyes, brows, lips and nostrils (each grown by `margin`: dlib's scatter).
cv::Mat SkinMask(std::span<const glm::vec2> landmarks, cv::Rect window, int margin) {
  const cv::Point origin = window.tl();
  cv::Mat mask = cv::Mat::zeros(window.size(), CV_8U);
  const std::vector<cv::Point> outline_points = ToPoints(FaceOutline(landmarks, 0.35f), origin);
  cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{outline_points}, cv::Scalar(255));
  cv::polylines(mask, std::vector<std::vector<cv::Point>>{outline_points}, true, cv::Scalar(0), 2 * margin);
  const std::vector<std::vector<cv::Point>> holes{
      Polygon(landmarks, dlib68::kRightEyeFirst, dlib68::kRightEyeLast, origin),
      Polygon(landmarks, dlib68::kLeftEyeFirst, dlib68::kLeftEyeLast, origin),
      Polygon(landmarks, dlib68::kOuterLipsFirst, dlib68::kOuterLipsLast, origin),
      Polygon(landmarks, dlib68::kNoseTip, dlib68::kNostrilsLast, origin)};
  cv::fillPoly(mask, holes, cv::Scalar(0));
  cv::polylines(mask, holes, true, cv::Scalar(0), 2 * margin);
  const std::vector<std::vector<cv::Point>> brows{
      Polygon(landmarks, dlib68::kRightBrowFirst, dlib68::kRightBrowLast, origin),
      Polygon(landmarks, dlib68::kLeftBrowFirst, dlib68::kLeftBrowLast, origin)};
  cv::polylines(mask, brows, false, cv::Scalar(0), 3 * margin);
  return mask;
}

// The mask without what the photo's colours say is not skin (hair over the
// forehead, a beard, the background past the cheeks): BuildPhotoSkinMask,
// which keeps the inner face whatever its colour.
void KeepSkinColoured(const RgbImage& photo, std::span<const glm::vec2> landmarks, cv::Rect window, cv::Mat& mask) {
  const PhotoSkinMask skin = BuildPhotoSkinMask(photo, landmarks);
  for (int y = 0; y < mask.rows; ++y) {
    for (int x = 0; x < mask.cols; ++x) {
      if (skin.At(x + window.x, y + window.y) < 0.5f) mask.at<std::uint8_t>(y, x) = 0;
    }
  }
}

// A sampled vertex and the region triangles round it (its normal's support).
struct Sample {
  std::uint32_t vertex = 0;
  std::vector<Triangle> ring;
};

// Mean edge length of the face region's triangles, model units.
float MeanEdge(const PhotoFaceModel& model, std::span<const glm::vec3> positions) {
  double sum = 0.0;
  for (const Triangle& t : model.region_triangles) sum += glm::length(positions[t[1]] - positions[t[0]]);
  return static_cast<float>(sum / static_cast<double>(std::max<std::size_t>(1, model.region_triangles.size())));
}

// Region vertices the photo shows as skin: in the mask, nearest the camera
// (the z-buffer of the posed fit) and facing it; at most max_samples, evenly.
std::vector<Sample> SelectSamples(const PhotoFaceModel& model, const PhotoFit& fit, const cv::Mat& mask,
                                  cv::Rect window, const PhotoShadingParams& params) {
  const Mesh mesh{.positions = fit.posed_positions, .triangles = model.visible_triangles};
  const RasterBuffers depth = Rasterize(mesh, fit.view);
  std::vector<glm::vec3> normals(fit.posed_positions.size());
  ComputeVertexNormals(fit.posed_positions, model.region_triangles, normals);
  const float tolerance = 3.0f / fit.camera.scale;
  std::vector<std::uint32_t> chosen;
  for (std::uint32_t v = model.region.first; v <= model.region.last; ++v) {
    const glm::vec3 p = ProjectToImage(fit.view, fit.posed_positions[v]);
    const int x = static_cast<int>(std::floor(p.x)), y = static_cast<int>(std::floor(p.y));
    if (!window.contains(cv::Point(x, y)) || mask.at<std::uint8_t>(y - window.y, x - window.x) == 0) continue;
    if (depth.triangle_ids[depth.index(x, y)] == kNoTriangle || depth.depths[depth.index(x, y)] > p.z + tolerance)
      continue;
    if ((fit.camera.rotation * normals[v]).z < params.min_facing) continue;
    chosen.push_back(v);
  }
  const std::size_t stride =
      std::max<std::size_t>(1, (chosen.size() + static_cast<std::size_t>(params.max_samples) - 1) /
                                   static_cast<std::size_t>(std::max(1, params.max_samples)));
  std::vector<int> slot(static_cast<std::size_t>(model.region.last) + 1, -1);
  std::vector<Sample> samples;
  for (std::size_t i = 0; i < chosen.size(); i += stride) {
    slot[chosen[i]] = static_cast<int>(samples.size());
    samples.push_back({chosen[i], {}});
  }
  for (const Triangle& t : model.region_triangles) {
    for (const std::uint32_t v : t) {
      if (slot[v] >= 0) samples[static_cast<std::size_t>(slot[v])].ring.push_back(t);
    }
  }
  return samples;
}

// One sample's state at the current weights.
struct Observation {
  bool valid = false;
  glm::vec3 colour{0.0f}, dx{0.0f}, dy{0.0f};  // blurred photo and its gradient
  glm::vec3 normal{0.0f};                      // unit, camera space
  glm::vec3 unnormalised{0.0f};                // world-space sum of the ring's face normals
  std::array<float, kHarmonics> y{};
  std::array<glm::vec3, kHarmonics> dy_dn{};
};

glm::vec3 RingNormal(const Sample& sample, std::span<const glm::vec3> positions) {
  glm::vec3 n(0.0f);
  for (const Triangle& t : sample.ring) {
    n += glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
  }
  return n;
}

// `view`: the photo's camera (perspective or not) where `camera` is its orthographic linearisation.
std::vector<Observation> Observe(const std::vector<Sample>& samples, std::span<const glm::vec3> positions,
                                 const ScaledOrthoCamera& camera, const RasterView& view, const BlurredWindow& photo) {
  std::vector<Observation> observations(samples.size());
  for (std::size_t s = 0; s < samples.size(); ++s) {
    Observation& o = observations[s];
    o.unnormalised = RingNormal(samples[s], positions);
    const float length = glm::length(o.unnormalised);
    if (!(length > 0.0f)) continue;
    const glm::vec2 pixel(ProjectToImage(view, positions[samples[s].vertex]));
    if (!photo.Sample(pixel, o.colour, o.dx, o.dy)) continue;
    o.normal = camera.rotation * (o.unnormalised / length);
    Harmonics(o.normal, o.y, o.dy_dn);
    o.valid = true;
  }
  return observations;
}

using Lighting = Eigen::Matrix<double, kHarmonics, 3>;

Eigen::Matrix<double, kHarmonics, 1> HarmonicVector(const Observation& o) {
  Eigen::Matrix<double, kHarmonics, 1> y;
  for (int k = 0; k < kHarmonics; ++k) y[k] = o.y[static_cast<std::size_t>(k)];
  return y;
}

// The lighting (9 coefficients per channel) best explaining the colours at
// the observations' normals, each observation weighted.
Lighting SolveLighting(const std::vector<Observation>& observations, const std::vector<double>& weights) {
  Eigen::Matrix<double, kHarmonics, kHarmonics> normal = Eigen::Matrix<double, kHarmonics, kHarmonics>::Zero();
  Lighting rhs = Lighting::Zero();
  for (std::size_t s = 0; s < observations.size(); ++s) {
    if (!observations[s].valid || weights[s] <= 0.0) continue;
    const auto y = HarmonicVector(observations[s]);
    const glm::vec3 c = observations[s].colour;
    normal += weights[s] * y * y.transpose();
    rhs += weights[s] * y * Eigen::RowVector3d(c.r, c.g, c.b);
  }
  normal.diagonal().array() += 1e-6 * (normal.trace() / kHarmonics + 1e-12);
  return normal.ldlt().solve(rhs);
}

Eigen::Vector3d Residual(const Observation& o, const Lighting& lighting) {
  const Eigen::Vector3d shade = lighting.transpose() * HarmonicVector(o);
  return Eigen::Vector3d(o.colour.r, o.colour.g, o.colour.b) - shade;
}

// Huber weights of the residuals' lengths and the per-channel noise (MAD).
double RobustWeights(const std::vector<Observation>& observations, const Lighting& lighting,
                     std::vector<double>& weights) {
  std::vector<double> lengths;
  for (const Observation& o : observations) {
    if (o.valid) lengths.push_back(Residual(o, lighting).norm());
  }
  if (lengths.empty()) return kMinNoise;
  std::vector<double> sorted = lengths;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  const double scale = std::max(1.4826 * sorted[sorted.size() / 2], std::sqrt(3.0) * kMinNoise);
  for (std::size_t s = 0, i = 0; s < observations.size(); ++s) {
    if (!observations[s].valid) {
      weights[s] = 0.0;
      continue;
    }
    const double e = lengths[i++];
    weights[s] = e <= kHuber * scale ? 1.0 : kHuber * scale / e;
  }
  return scale / std::sqrt(3.0);
}

// The posed shape's face region (vertices 0 .. region.last).
std::vector<glm::vec3> PosedRegion(const PhotoFaceModel& model, const Eigen::VectorXd& weights) {
  return photo_shape::ShapeOf(model, weights, 0, static_cast<std::size_t>(model.region.last) + 1,
                              model.unknown_count());
}

// How the ring's unnormalised normal moves along `mode`.
glm::vec3 NormalChange(const Sample& sample, std::span<const glm::vec3> positions, const std::vector<glm::vec3>& mode) {
  glm::vec3 change(0.0f);
  for (const Triangle& t : sample.ring) {
    change += glm::cross(mode[t[1]] - mode[t[0]], positions[t[2]] - positions[t[0]]) +
              glm::cross(positions[t[1]] - positions[t[0]], mode[t[2]] - mode[t[0]]);
  }
  return change;
}

// The camera's unknowns, ahead of the weights: a small rotation about the
// camera's axes, the log of the scale and the translation (pixels, y up).
constexpr Eigen::Index kCameraUnknowns = 6;

// How a camera-space point's pixel moves with the camera's unknowns.
Eigen::Matrix<double, 2, kCameraUnknowns> PixelByCamera(glm::vec3 camera_point, float scale) {
  Eigen::Matrix<double, 2, kCameraUnknowns> d;
  for (int j = 0; j < 3; ++j) {
    glm::vec3 axis(0.0f);
    axis[j] = 1.0f;
    const glm::vec3 turned = glm::cross(axis, camera_point);
    d(0, j) = scale * turned.x;
    d(1, j) = -scale * turned.y;
  }
  d.col(3) << scale * camera_point.x, -scale * camera_point.y;
  d.col(4) << 1.0, 0.0;
  d.col(5) << 0.0, -1.0;
  return d;
}

// How a vertex's pixel moves with each mode's weight (2 x modes).
Eigen::MatrixXd PixelByWeights(const PhotoFaceModel& model, const ScaledOrthoCamera& camera, std::uint32_t vertex) {
  const auto n = static_cast<Eigen::Index>(model.unknown_count());
  Eigen::MatrixXd d(2, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const glm::vec3 moved = camera.rotation * photo_shape::Mode(model, static_cast<std::size_t>(i))[vertex];
    d(0, i) = camera.scale * moved.x;
    d(1, i) = -camera.scale * moved.y;
  }
  return d;
}

struct ShadingContext {
  const PhotoFaceModel& model;
  const std::vector<Sample>& samples;
};

// The landmark term and prior over camera and weights: FitPhoto's system in
// the weights (exact for a fixed camera) and the camera linearised.
photo_shape::LinearSystem LandmarkSystem(const PhotoFaceModel& model, const ScaledOrthoCamera& camera,
                                         std::span<const glm::vec2> targets, std::span<const std::uint32_t> vertices,
                                         std::span<const glm::vec3> positions, std::span<const glm::vec2> precisions,
                                         int width, int height, const PhotoFitParams& params) {
  const photo_shape::LinearSystem weights =
      photo_shape::BuildSystem(model, camera, targets, vertices, precisions, width, height, params);
  const Eigen::Index n = weights.rhs.size(), total = kCameraUnknowns + n;
  photo_shape::LinearSystem system{Eigen::MatrixXd::Zero(total, total), Eigen::VectorXd::Zero(total)};
  system.normal.bottomRightCorner(n, n) = weights.normal;
  system.rhs.tail(n) = weights.rhs;
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    const Eigen::Matrix<double, 2, kCameraUnknowns> by_camera =
        PixelByCamera(camera.rotation * positions[vertices[k]], camera.scale);
    const Eigen::MatrixXd by_weights = PixelByWeights(model, camera, vertices[k]);
    const Eigen::Matrix2d precision = Eigen::Vector2d(precisions[k].x, precisions[k].y).asDiagonal();
    const glm::vec2 from_neutral = targets[k] - ProjectPixel(camera, model.neutral[vertices[k]], width, height);
    system.normal.topLeftCorner(kCameraUnknowns, kCameraUnknowns) += by_camera.transpose() * precision * by_camera;
    const Eigen::MatrixXd cross = by_camera.transpose() * precision * by_weights;
    system.normal.topRightCorner(kCameraUnknowns, n) += cross;
    system.normal.bottomLeftCorner(n, kCameraUnknowns) += cross.transpose();
    system.rhs.head(kCameraUnknowns) +=
        by_camera.transpose() * precision * Eigen::Vector2d(from_neutral.x, from_neutral.y);
  }
  return system;
}

// The shading residuals linearised in camera and weights (3 rows per
// observation: the photo's change as the vertex moves across it, minus the
// shade's as its normal turns), added to `system` about `current` (camera
// unknowns zero) with `precision` times each observation's robust weight.
void AddShadingTerm(const ShadingContext& context, const ScaledOrthoCamera& camera,
                    const std::vector<Observation>& observations, std::span<const glm::vec3> positions,
                    const Lighting& lighting, const std::vector<double>& weights, double precision,
                    const Eigen::VectorXd& current, photo_shape::LinearSystem& system) {
  const auto n = static_cast<Eigen::Index>(context.model.unknown_count());
  const auto valid = static_cast<Eigen::Index>(
      std::count_if(observations.begin(), observations.end(), [](const Observation& o) { return o.valid; }));
  Eigen::MatrixXd jacobian(3 * valid, kCameraUnknowns + n);
  Eigen::VectorXd residual(3 * valid), row_weights(3 * valid);
  Eigen::Index row = 0;
  for (std::size_t s = 0; s < observations.size(); ++s) {
    const Observation& o = observations[s];
    if (!o.valid) continue;
    const std::uint32_t vertex = context.samples[s].vertex;
    const float length = glm::length(o.unnormalised);
    const glm::vec3 unit = o.unnormalised / length;
    Eigen::Matrix<double, 3, 2> image_gradient;
    Eigen::Matrix3d shade_gradient = Eigen::Matrix3d::Zero();  // rows: channels; columns: normal (camera space)
    for (int c = 0; c < 3; ++c) {
      image_gradient.row(c) << o.dx[c], o.dy[c];
      for (int k = 0; k < kHarmonics; ++k) {
        for (int a = 0; a < 3; ++a) shade_gradient(c, a) += lighting(k, c) * o.dy_dn[static_cast<std::size_t>(k)][a];
      }
    }
    Eigen::Matrix3d normal_by_rotation;  // columns: the normal's turn about each camera axis
    for (int j = 0; j < 3; ++j) {
      glm::vec3 axis(0.0f);
      axis[j] = 1.0f;
      const glm::vec3 turned = glm::cross(axis, o.normal);
      normal_by_rotation.col(j) << turned.x, turned.y, turned.z;
    }
    jacobian.block(row, 0, 3, kCameraUnknowns) =
        image_gradient * PixelByCamera(camera.rotation * positions[vertex], camera.scale);
    jacobian.block(row, 0, 3, 3) -= shade_gradient * normal_by_rotation;
    const Eigen::MatrixXd by_weights = PixelByWeights(context.model, camera, vertex);
    for (Eigen::Index i = 0; i < n; ++i) {
      const glm::vec3 raw =
          NormalChange(context.samples[s], positions, photo_shape::Mode(context.model, static_cast<std::size_t>(i)));
      const glm::vec3 turned = camera.rotation * ((raw - unit * glm::dot(unit, raw)) / length);
      jacobian.block(row, kCameraUnknowns + i, 3, 1) =
          image_gradient * by_weights.col(i) - shade_gradient * Eigen::Vector3d(turned.x, turned.y, turned.z);
    }
    residual.segment<3>(row) = Residual(o, lighting);
    row_weights.segment<3>(row).setConstant(precision * weights[s]);
    row += 3;
  }
  const Eigen::MatrixXd weighted = row_weights.asDiagonal() * jacobian;
  const Eigen::MatrixXd hessian = jacobian.transpose() * weighted;
  system.normal += hessian;
  system.rhs += hessian * current - weighted.transpose() * residual;
}

// The camera's unknowns held at zero.
void FixCamera(photo_shape::LinearSystem& system) {
  system.normal.topRows(kCameraUnknowns).setZero();
  system.normal.leftCols(kCameraUnknowns).setZero();
  system.normal.topLeftCorner(kCameraUnknowns, kCameraUnknowns).setIdentity();
  system.rhs.head(kCameraUnknowns).setZero();
}

// The camera moved by the solved unknowns.
ScaledOrthoCamera MovedCamera(const ScaledOrthoCamera& camera, const Eigen::VectorXd& step) {
  const glm::vec3 rotation_vector(static_cast<float>(step[0]), static_cast<float>(step[1]),
                                  static_cast<float>(step[2]));
  const float angle = glm::length(rotation_vector);
  glm::mat3 turn(1.0f);
  if (angle > 0.0f) {
    const glm::vec3 a = rotation_vector / angle;
    const glm::mat3 k(0.0f, a.z, -a.y, -a.z, 0.0f, a.x, a.y, -a.x, 0.0f);  // cross-product matrix (columns)
    turn = glm::mat3(1.0f) + std::sin(angle) * k + (1.0f - std::cos(angle)) * k * k;
  }
  ScaledOrthoCamera moved = camera;
  moved.rotation = turn * camera.rotation;
  moved.scale = camera.scale * std::exp(static_cast<float>(step[3]));
  moved.translation += glm::vec2(static_cast<float>(step[4]), static_cast<float>(step[5]));
  return moved;
}

void CheckInputs(const RgbImage& photo, std::span<const glm::vec2> detected) {
  if (photo.width <= 0 || photo.height <= 0 ||
      photo.pixels.size() != 3 * static_cast<std::size_t>(photo.width) * static_cast<std::size_t>(photo.height)) {
    throw InvalidInputError("photo shading fit: the photo's pixels do not match its size", "photo");
  }
  if (detected.size() != kDlibLandmarkCount) {
    throw InvalidInputError("photo shading fit: expected 68 landmarks, got " + std::to_string(detected.size()),
                            "landmarks");
  }
}

// The landmarks' box grown to the forehead and by `margin`, within the photo.
cv::Rect FaceWindow(std::span<const glm::vec2> landmarks, int width, int height, double face_size, int margin) {
  const PixelBox box = BoxAround(landmarks);
  glm::vec2 low = box.low;
  const glm::vec2 high = box.high;
  low.y -= 0.4f * static_cast<float>(face_size);
  return cv::Rect(cv::Point(static_cast<int>(low.x) - margin, static_cast<int>(low.y) - margin),
                  cv::Point(static_cast<int>(high.x) + margin + 1, static_cast<int>(high.y) + margin + 1)) &
         cv::Rect(0, 0, width, height);
}

std::vector<glm::vec3> PointsOf(std::span<const glm::vec3> positions, std::span<const std::uint32_t> vertices) {
  std::vector<glm::vec3> points;
  for (const std::uint32_t v : vertices) points.push_back(positions[v]);
  return points;
}

Eigen::VectorXd WeightsOf(const PhotoFit& fit) {
  Eigen::VectorXd weights(static_cast<Eigen::Index>(fit.identity_weights.size() + fit.expression_weights.size()));
  Eigen::Index i = 0;
  for (const float w : fit.identity_weights) weights[i++] = w;
  for (const float w : fit.expression_weights) weights[i++] = w;
  return weights;
}

// The fewest skin samples worth a shading term.
constexpr std::size_t kMinSamples = 100;

// The lighting at the final weights and camera, robustly weighted.
std::vector<glm::vec3> FinalLighting(const PhotoFaceModel& model, const std::vector<Sample>& samples,
                                     const Eigen::VectorXd& weights, const PhotoFit& refined, const BlurredWindow& blurred) {
  const std::vector<glm::vec3> positions = PosedRegion(model, weights);
  const std::vector<Observation> observations = Observe(samples, positions, refined.camera, refined.view, blurred);
  std::vector<double> robust(observations.size(), 1.0);
  RobustWeights(observations, SolveLighting(observations, robust), robust);
  const Lighting lighting = SolveLighting(observations, robust);
  std::vector<glm::vec3> coefficients(kHarmonics);
  for (int k = 0; k < kHarmonics; ++k) {
    coefficients[static_cast<std::size_t>(k)] = glm::vec3(lighting(k, 0), lighting(k, 1), lighting(k, 2));
  }
  return coefficients;
}

}  // namespace

glm::vec3 EvaluatePhotoLighting(std::span<const glm::vec3> lighting, glm::vec3 camera_normal) {
  if (lighting.size() != static_cast<std::size_t>(kHarmonics)) return glm::vec3(0.0f);
  std::array<float, kHarmonics> y{};
  std::array<glm::vec3, kHarmonics> dy{};
  Harmonics(camera_normal, y, dy);
  glm::vec3 colour(0.0f);
  for (std::size_t k = 0; k < y.size(); ++k) colour += y[k] * lighting[k];
  return colour;
}

PhotoFit RefinePhotoFitByShading(const PhotoFaceModel& model, const RgbImage& photo,
                                 std::span<const glm::vec2> detected, const PhotoFit& fit,
                                 const PhotoFitParams& params) {
  const auto start = std::chrono::steady_clock::now();
  CheckInputs(photo, detected);
  if (model.identity_modes.empty() || fit.deformed || fit.posed_positions.size() != model.neutral.size()) return fit;
  const std::span<const glm::vec2> targets =
      fit.target_pixels.size() == kDlibLandmarkCount ? std::span<const glm::vec2>(fit.target_pixels) : detected;
  const double face_size = photo_shape::FaceSize(detected);
  const double blur = std::max(0.5, static_cast<double>(params.shading_params.blur_edges *
                                                        MeanEdge(model, fit.posed_positions) * fit.camera.scale));
  const int margin = std::max(1, static_cast<int>(std::lround(0.03 * face_size)));
  const cv::Rect window =
      FaceWindow(detected, photo.width, photo.height, face_size, margin + static_cast<int>(std::ceil(3.0 * blur)));
  if (window.width < 8 || window.height < 8) return fit;
  const BlurredWindow blurred = BlurPhoto(photo, window, blur);
  cv::Mat mask = SkinMask(detected, window, margin);
  KeepSkinColoured(photo, detected, window, mask);
  const std::vector<Sample> samples = SelectSamples(model, fit, mask, window, params.shading_params);
  if (samples.size() < kMinSamples) return fit;
  const std::vector<glm::vec2> precisions = photo_shape::LandmarkPrecisions(params, face_size);
  const ShadingContext context{model, samples};
  const Eigen::Index n = static_cast<Eigen::Index>(model.unknown_count());
  Eigen::VectorXd current = Eigen::VectorXd::Zero(kCameraUnknowns + n);
  current.tail(n) = WeightsOf(fit);
  ScaledOrthoCamera camera = fit.camera;
  for (int iteration = 0; iteration < params.shading_params.iterations; ++iteration) {
    const std::vector<glm::vec3> positions = PosedRegion(model, current.tail(n));
    // A perspective photo: the landmarks and samples as the orthographic camera would see them.
    const std::vector<glm::vec3> landmark_points = PointsOf(positions, fit.landmark_vertices);
    const std::vector<glm::vec2> seen =
        OrthographicPixels(targets, landmark_points, camera, fit.camera_distance, photo.width, photo.height);
    const RasterView view =
        ToPerspectiveView(camera, photo.width, photo.height, photo_shape::Centroid(landmark_points), fit.camera_distance);
    const std::vector<Observation> observations = Observe(samples, positions, camera, view, blurred);
    std::vector<double> robust(observations.size(), 1.0);
    Lighting lighting = SolveLighting(observations, robust);
    const double noise = RobustWeights(observations, lighting, robust);
    lighting = SolveLighting(observations, robust);
    photo_shape::LinearSystem system = LandmarkSystem(model, camera, seen, fit.landmark_vertices, positions,
                                                      precisions, photo.width, photo.height, params);
    AddShadingTerm(context, camera, observations, positions, lighting, robust,
                   params.shading_params.weight / (noise * noise), current, system);
    if (!params.shading_params.camera) FixCamera(system);
    const Eigen::VectorXd solved =
        photo_shape::SolveBounded(system, static_cast<std::size_t>(kCameraUnknowns) + model.identity_modes.size());
    camera = MovedCamera(camera, solved);
    current.tail(n) = solved.tail(n);
  }
  PhotoFit refined = fit;
  refined.camera = camera;
  photo_shape::FillResult(model, current.tail(n), targets, photo.width, photo.height, refined);
  refined.lighting = FinalLighting(model, samples, current.tail(n), refined, blurred);
  refined.seconds = fit.seconds + SecondsSince(start);
  return refined;
}

PhotoFit FitPhoto(const PhotoFaceModel& model, const RgbImage& photo, std::span<const glm::vec2> landmarks,
                  const PhotoFitParams& params) {
  const PhotoFit fit = FitPhoto(model, landmarks, photo.width, photo.height, params);
  return params.shading ? RefinePhotoFitByShading(model, photo, landmarks, fit, params) : fit;
}

}  // namespace facerig
