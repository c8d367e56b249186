// The scaled orthographic camera of a photo from 2D-3D landmark pairs: the
// least-squares affine camera, its nearest scaled rotation, then a few
// Gauss-Newton steps on rotation, scale and translation together.
#include <cmath>
#include <string>

#include <Eigen/Dense>
#include <glm/geometric.hpp>

#include "facerig/offline/error.h"
#include "facerig/offline/photo/fit.h"

namespace facerig {

namespace {

constexpr int kRefineSteps = 4;

// Pixel (y down) -> centred coordinates (y up).
Eigen::Vector2d Centred(glm::vec2 pixel, int width, int height) {
  return {pixel.x - 0.5 * width, 0.5 * height - pixel.y};
}

Eigen::Vector3d ToEigen(glm::vec3 p) { return {p.x, p.y, p.z}; }

struct CameraState {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  double scale = 1.0;
  Eigen::Vector2d translation = Eigen::Vector2d::Zero();
};

CameraState AffineCamera(std::span<const glm::vec3> points, std::span<const Eigen::Vector2d> targets,
                         std::span<const float> weights) {
  Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
  Eigen::Matrix<double, 4, 2> rhs = Eigen::Matrix<double, 4, 2>::Zero();
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Eigen::Vector4d row(points[k].x, points[k].y, points[k].z, 1.0);
    normal += weights[k] * row * row.transpose();
    rhs += weights[k] * row * targets[k].transpose();
  }
  const Eigen::Matrix<double, 4, 2> affine = normal.ldlt().solve(rhs);
  const Eigen::Matrix<double, 2, 3> linear = affine.topRows<3>().transpose();
  const Eigen::JacobiSVD<Eigen::Matrix<double, 2, 3>> svd(linear, Eigen::ComputeFullU | Eigen::ComputeFullV);
  CameraState camera;
  const Eigen::Matrix<double, 2, 3> rows = svd.matrixU() * svd.matrixV().leftCols<2>().transpose();
  camera.rotation.row(0) = rows.row(0);
  camera.rotation.row(1) = rows.row(1);
  camera.rotation.row(2) = rows.row(0).cross(rows.row(1));
  camera.scale = 0.5 * (svd.singularValues()[0] + svd.singularValues()[1]);
  camera.translation = affine.row(3).transpose();
  if (!std::isfinite(camera.scale) || camera.scale <= 0.0 || !camera.rotation.allFinite()) {
    throw InvalidInputError("photo camera: the landmark configuration is degenerate", "landmarks");
  }
  return camera;
}

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// Unknowns: a small rotation (3), scale, translation (2).
void GaussNewtonStep(std::span<const glm::vec3> points, std::span<const Eigen::Vector2d> targets,
                     std::span<const float> weights, CameraState& camera) {
  Eigen::Matrix<double, 6, 6> normal = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Eigen::Vector3d rotated = camera.rotation * ToEigen(points[k]);
    const Eigen::Vector2d residual = targets[k] - (camera.scale * rotated.head<2>() + camera.translation);
    Eigen::Matrix<double, 2, 6> jacobian;
    jacobian.leftCols<3>() = -camera.scale * Skew(rotated).topRows<2>();
    jacobian.col(3) = rotated.head<2>();
    jacobian.rightCols<2>() = Eigen::Matrix2d::Identity();
    normal += weights[k] * jacobian.transpose() * jacobian;
    rhs += weights[k] * jacobian.transpose() * residual;
  }
  const Eigen::Matrix<double, 6, 1> step = normal.ldlt().solve(rhs);
  if (!step.allFinite()) return;
  const Eigen::Vector3d omega = step.head<3>();
  if (omega.norm() > 0.0) {
    camera.rotation = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix() * camera.rotation;
  }
  camera.scale += step[3];
  camera.translation += step.tail<2>();
}

}  // namespace

ScaledOrthoCamera FitScaledOrthoCamera(std::span<const glm::vec3> points, std::span<const glm::vec2> pixels,
                                       std::span<const float> weights, int width, int height) {
  if (points.size() != pixels.size() || points.size() < 4 || (!weights.empty() && weights.size() != points.size())) {
    throw InvalidInputError("photo camera: need at least 4 point pairs (and as many weights), got " +
                                std::to_string(points.size()) + " points and " + std::to_string(pixels.size()) +
                                " pixels",
                            "landmarks");
  }
  std::vector<Eigen::Vector2d> targets;
  for (const glm::vec2 p : pixels) targets.push_back(Centred(p, width, height));
  const std::vector<float> unit(points.size(), 1.0f);
  const std::span<const float> w = weights.empty() ? std::span<const float>(unit) : weights;
  CameraState camera = AffineCamera(points, targets, w);
  for (int step = 0; step < kRefineSteps; ++step) GaussNewtonStep(points, targets, w, camera);
  ScaledOrthoCamera out;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out.rotation[c][r] = static_cast<float>(camera.rotation(r, c));  // glm: [column][row]
  }
  out.scale = static_cast<float>(camera.scale);
  out.translation = {static_cast<float>(camera.translation.x()), static_cast<float>(camera.translation.y())};
  return out;
}

glm::vec2 ProjectPixel(const ScaledOrthoCamera& camera, glm::vec3 point, int width, int height) {
  const glm::vec3 rotated = camera.rotation * point;
  return {0.5f * static_cast<float>(width) + camera.scale * rotated.x + camera.translation.x,
          0.5f * static_cast<float>(height) - (camera.scale * rotated.y + camera.translation.y)};
}

RasterView ToRasterView(const ScaledOrthoCamera& camera, int width, int height, glm::vec3 depth_centre) {
  RasterView view;
  view.rotation = camera.rotation;
  view.width = width;
  view.height = height;
  view.half_extent = 0.5f * static_cast<float>(height) / camera.scale;
  // rotation * (x - centre) * scale == rotation * x * scale + translation in x and y.
  const glm::vec3 right(camera.rotation[0][0], camera.rotation[1][0], camera.rotation[2][0]);
  const glm::vec3 up(camera.rotation[0][1], camera.rotation[1][1], camera.rotation[2][1]);
  const glm::vec3 forward(camera.rotation[0][2], camera.rotation[1][2], camera.rotation[2][2]);
  view.centre = -(camera.translation.x / camera.scale) * right - (camera.translation.y / camera.scale) * up +
                glm::dot(depth_centre, forward) * forward;
  return view;
}

}  // namespace facerig
