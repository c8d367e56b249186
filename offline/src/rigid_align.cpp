#include "facerig/offline/rigid_align.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include <Eigen/Dense>
#include <glm/geometric.hpp>

#include "facerig/offline/closest_point.h"
#include "facerig/offline/registration_error.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {
namespace {

Eigen::Vector3d ToEigen(glm::vec3 v) { return {v.x, v.y, v.z}; }
glm::vec3 ToGlm(const Eigen::Vector3d& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

bool Finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Eigen::Matrix3d AxisAngle(const Eigen::Vector3d& omega) {
  const double angle = omega.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix();
}

}  // namespace

glm::vec3 SimilarityTransform::Apply(glm::vec3 p) const {
  return ToGlm(scale * (rotation * ToEigen(p)) + translation);
}

glm::vec3 SimilarityTransform::ApplyToDirection(glm::vec3 d) const { return ToGlm(rotation * ToEigen(d)); }

SimilarityTransform SimilarityTransform::Inverse() const {
  SimilarityTransform inverse;
  inverse.scale = 1.0 / scale;
  inverse.rotation = rotation.transpose();
  inverse.translation = -(inverse.scale * (inverse.rotation * translation));
  return inverse;
}

SimilarityTransform SimilarityTransform::operator*(const SimilarityTransform& other) const {
  SimilarityTransform result;
  result.scale = scale * other.scale;
  result.rotation = rotation * other.rotation;
  result.translation = scale * (rotation * other.translation) + translation;
  return result;
}

void CheckMesh(std::span<const glm::vec3> positions, std::span<const Triangle> triangles, const char* what) {
  if (positions.empty() || triangles.empty()) {
    throw InvalidInputError(std::string(what) + ": the mesh is empty (" + std::to_string(positions.size()) +
                            " vertices, " + std::to_string(triangles.size()) + " triangles)");
  }
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (!Finite(positions[v])) {
      throw InvalidInputError(std::string(what) + ": vertex " + std::to_string(v) +
                              " has a NaN or infinite coordinate");
    }
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (std::uint32_t v : triangles[t]) {
      if (v >= positions.size()) {
        throw InvalidInputError(std::string(what) + ": triangle " + std::to_string(t) + " uses vertex " +
                                std::to_string(v) + " but the mesh has " + std::to_string(positions.size()));
      }
    }
  }
}

SimilarityTransform Umeyama(std::span<const glm::vec3> source, std::span<const glm::vec3> target,
                            std::span<const float> weights, bool with_scale) {
  if (source.size() != target.size()) {
    throw InvalidInputError("Umeyama: " + std::to_string(source.size()) + " source points but " +
                            std::to_string(target.size()) + " target points");
  }
  if (!weights.empty() && weights.size() != source.size()) {
    throw InvalidInputError("Umeyama: weights must be empty or one per point");
  }
  double total = 0.0;
  std::size_t used = 0;
  Eigen::Vector3d mean_source = Eigen::Vector3d::Zero(), mean_target = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < source.size(); ++i) {
    if (!Finite(source[i]) || !Finite(target[i])) {
      throw InvalidInputError("Umeyama: point pair " + std::to_string(i) + " is not finite");
    }
    const double w = weights.empty() ? 1.0 : static_cast<double>(weights[i]);
    if (!(w >= 0.0)) throw InvalidInputError("Umeyama: negative or NaN weight at " + std::to_string(i));
    if (w == 0.0) continue;
    ++used;
    total += w;
    mean_source += w * ToEigen(source[i]);
    mean_target += w * ToEigen(target[i]);
  }
  if (used < 3) throw InvalidInputError("Umeyama: needs at least 3 point pairs with positive weight");
  mean_source /= total;
  mean_target /= total;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double source_variance = 0.0;
  for (std::size_t i = 0; i < source.size(); ++i) {
    const double w = weights.empty() ? 1.0 : static_cast<double>(weights[i]);
    if (w == 0.0) continue;
    const Eigen::Vector3d s = ToEigen(source[i]) - mean_source;
    const Eigen::Vector3d t = ToEigen(target[i]) - mean_target;
    covariance += w * t * s.transpose();
    source_variance += w * s.squaredNorm();
  }
  covariance /= total;
  source_variance /= total;
  if (!(source_variance > 0.0)) throw InvalidInputError("Umeyama: all source points coincide");

  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d signs = Eigen::Vector3d::Ones();
  // A reflection would fit better than any rotation: flip the weakest axis.
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) signs.z() = -1.0;
  SimilarityTransform result;
  result.rotation = svd.matrixU() * signs.asDiagonal() * svd.matrixV().transpose();
  result.scale = with_scale ? svd.singularValues().dot(signs) / source_variance : 1.0;
  result.translation = mean_target - result.scale * (result.rotation * mean_source);
  return result;
}

RigidAlignResult RigidAlign(std::span<const glm::vec3> source_positions,
                            std::span<const Triangle> source_triangles,
                            std::span<const glm::vec3> target_positions,
                            std::span<const Triangle> target_triangles,
                            std::span<const glm::vec3> source_landmarks,
                            std::span<const glm::vec3> target_landmarks, const RigidAlignParams& params,
                            const SimilarityTransform* initial) {
  CheckMesh(target_positions, target_triangles, "rigid alignment target");
  const ClosestPointQuery target(target_positions, target_triangles);
  return RigidAlign(source_positions, source_triangles, target, source_landmarks, target_landmarks, params,
                    initial);
}

RigidAlignResult RigidAlign(std::span<const glm::vec3> source_positions,
                            std::span<const Triangle> source_triangles, const ClosestPointQuery& target,
                            std::span<const glm::vec3> source_landmarks,
                            std::span<const glm::vec3> target_landmarks, const RigidAlignParams& params,
                            const SimilarityTransform* initial) {
  const auto start = std::chrono::steady_clock::now();
  CheckMesh(source_positions, source_triangles, "rigid alignment source");
  if (source_landmarks.size() != target_landmarks.size()) {
    throw InvalidInputError("rigid alignment: " + std::to_string(source_landmarks.size()) +
                            " source landmarks but " + std::to_string(target_landmarks.size()) +
                            " target landmarks");
  }
  RigidAlignResult result;

  std::vector<glm::vec3> source_normals(source_positions.size());
  ComputeVertexNormals(source_positions, source_triangles, source_normals);
  // Only vertices used by a triangle take part (loose vertices have no normal).
  std::vector<std::uint32_t> used;
  {
    std::vector<std::uint8_t> referenced(source_positions.size(), 0);
    for (const Triangle& t : source_triangles) {
      for (std::uint32_t v : t) referenced[v] = 1;
    }
    for (std::uint32_t v = 0; v < referenced.size(); ++v) {
      if (referenced[v] && glm::dot(source_normals[v], source_normals[v]) > 0.5f) used.push_back(v);
    }
  }
  const std::size_t stride = std::max<std::size_t>(1, (used.size() + params.max_samples - 1) /
                                                          std::max<std::size_t>(1, params.max_samples));
  std::vector<std::uint32_t> samples;
  for (std::size_t i = 0; i < used.size(); i += stride) samples.push_back(used[i]);
  if (samples.empty()) throw InvalidInputError("rigid alignment source: no vertex belongs to a triangle");

  SimilarityTransform transform;
  if (source_landmarks.size() >= 3) {
    transform = Umeyama(source_landmarks, target_landmarks, {}, params.with_scale);
  } else if (initial != nullptr) {
    transform = *initial;
  } else {
    // Centroids and RMS radii: right scale and position, no rotation.
    auto moments = [](std::span<const glm::vec3> points, auto&& index, std::size_t count) {
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (std::size_t i = 0; i < count; ++i) mean += ToEigen(points[index(i)]);
      mean /= static_cast<double>(count);
      double variance = 0.0;
      for (std::size_t i = 0; i < count; ++i) variance += (ToEigen(points[index(i)]) - mean).squaredNorm();
      return std::pair{mean, std::sqrt(variance / static_cast<double>(count))};
    };
    const auto [source_mean, source_radius] =
        moments(source_positions, [&](std::size_t i) { return samples[i]; }, samples.size());
    const auto target_points = target.positions();
    const auto [target_mean, target_radius] =
        moments(target_points, [](std::size_t i) { return i; }, target_points.size());
    transform.scale = params.with_scale && source_radius > 0.0 ? target_radius / source_radius : 1.0;
    transform.translation = target_mean - transform.scale * source_mean;
  }

  const double cos_limit = std::cos(params.max_normal_angle_degrees * 3.14159265358979323846 / 180.0);
  std::vector<glm::vec3> points(samples.size()), normals(samples.size());
  std::vector<ClosestPointHit> hits(samples.size());
  std::vector<float> distances;
  const int unknowns = params.with_scale ? 7 : 6;
  for (int iteration = 0; iteration < params.max_iterations; ++iteration) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < samples.size(); ++i) {
      points[i] = transform.Apply(source_positions[samples[i]]);
      normals[i] = transform.ApplyToDirection(source_normals[samples[i]]);
      hits[i] = target.Find(points[i]);
      centre += ToEigen(points[i]);
    }
    centre /= static_cast<double>(samples.size());
    distances.clear();
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const bool compatible = glm::dot(normals[i], hits[i].normal) >= cos_limit;
      if (compatible && !(params.reject_boundary && hits[i].on_boundary)) distances.push_back(hits[i].distance);
    }
    if (distances.size() < 6) break;
    std::nth_element(distances.begin(), distances.begin() + static_cast<std::ptrdiff_t>(distances.size() / 2),
                     distances.end());
    const double median = distances[distances.size() / 2];
    const double limit = params.outlier_median_factor * median + 1e-12;

    Eigen::Matrix<double, 7, 7> normal_matrix = Eigen::Matrix<double, 7, 7>::Zero();
    Eigen::Matrix<double, 7, 1> rhs = Eigen::Matrix<double, 7, 1>::Zero();
    auto add_row = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& n, double residual, double w) {
      Eigen::Matrix<double, 7, 1> row;
      const Eigen::Vector3d local = p - centre;
      row.head<3>() = local.cross(n);
      row.segment<3>(3) = n;
      row(6) = n.dot(local);
      normal_matrix.noalias() += w * row * row.transpose();
      rhs.noalias() += w * residual * row;
    };
    std::size_t inliers = 0;
    double squared_sum = 0.0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const ClosestPointHit& hit = hits[i];
      if (hit.distance > limit || (params.reject_boundary && hit.on_boundary) ||
          glm::dot(normals[i], hit.normal) < cos_limit) {
        continue;
      }
      const Eigen::Vector3d n = ToEigen(hit.normal);
      const Eigen::Vector3d p = ToEigen(points[i]);
      const double residual = n.dot(ToEigen(hit.point) - p);
      add_row(p, n, residual, 1.0);
      squared_sum += static_cast<double>(hit.distance) * hit.distance;
      ++inliers;
    }
    if (inliers < 6) break;
    if (iteration == 0) result.rms_initial = std::sqrt(squared_sum / static_cast<double>(inliers));
    result.rms_final = std::sqrt(squared_sum / static_cast<double>(inliers));
    result.inliers = inliers;
    if (!source_landmarks.empty() && params.landmark_weight > 0.0) {
      const double w = params.landmark_weight * static_cast<double>(inliers) /
                       static_cast<double>(source_landmarks.size());
      for (std::size_t l = 0; l < source_landmarks.size(); ++l) {
        const Eigen::Vector3d p = ToEigen(transform.Apply(source_landmarks[l]));
        const Eigen::Vector3d q = ToEigen(target_landmarks[l]);
        for (int axis = 0; axis < 3; ++axis) {
          const Eigen::Vector3d n = Eigen::Vector3d::Unit(axis);
          add_row(p, n, q(axis) - p(axis), w);
        }
      }
    }
    Eigen::Matrix<double, 7, 1> delta = Eigen::Matrix<double, 7, 1>::Zero();
    // Tiny Tikhonov term: a flat patch leaves the in-plane motion undetermined.
    const double ridge = 1e-9 * normal_matrix.trace();
    const Eigen::MatrixXd a = normal_matrix.topLeftCorner(unknowns, unknowns) +
                              ridge * Eigen::MatrixXd::Identity(unknowns, unknowns);
    delta.head(unknowns) = a.ldlt().solve(rhs.head(unknowns));
    if (!delta.allFinite()) throw SolverError("rigid alignment: the ICP step is not finite");

    SimilarityTransform step;
    step.scale = std::exp(delta(6));
    step.rotation = AxisAngle(delta.head<3>());
    step.translation = centre + delta.segment<3>(3) - step.scale * (step.rotation * centre);
    transform = step * transform;
    result.iterations = iteration + 1;

    double radius = 0.0;
    for (const glm::vec3& p : points) radius = std::max(radius, (ToEigen(p) - centre).norm());
    const double motion = delta.head<3>().norm() * radius + delta.segment<3>(3).norm() +
                          std::abs(delta(6)) * radius;
    if (motion < params.convergence * std::max(radius, 1e-30)) break;
  }

  if (!source_landmarks.empty()) {
    double sum = 0.0;
    for (std::size_t l = 0; l < source_landmarks.size(); ++l) {
      sum += static_cast<double>(glm::dot(transform.Apply(source_landmarks[l]) - target_landmarks[l],
                                          transform.Apply(source_landmarks[l]) - target_landmarks[l]));
    }
    result.landmark_rms = std::sqrt(sum / static_cast<double>(source_landmarks.size()));
  }
  result.transform = transform;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace facerig
