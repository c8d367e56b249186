#include "facerig/offline/geometry/similarity.h"

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "facerig/offline/error.h"

namespace facerig {
namespace {

Eigen::Vector3d ToEigen(glm::vec3 v) { return {v.x, v.y, v.z}; }
glm::vec3 ToGlm(const Eigen::Vector3d& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

bool Finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

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

SimilarityTransform FitRigid(std::span<const glm::vec3> moving, std::span<const glm::vec3> fixed,
                             std::span<const std::uint32_t> subset, double* rms) {
  if (moving.size() != fixed.size()) {
    throw InvalidInputError("rigid fit: " + std::to_string(moving.size()) + " moving points but " +
                            std::to_string(fixed.size()) + " fixed points");
  }
  std::vector<glm::vec3> from, to;
  if (subset.empty()) {
    from.assign(moving.begin(), moving.end());
    to.assign(fixed.begin(), fixed.end());
  }
  for (std::uint32_t v : subset) {
    if (v >= moving.size()) throw InvalidInputError("rigid fit: vertex " + std::to_string(v) + " out of range");
    from.push_back(moving[v]);
    to.push_back(fixed[v]);
  }
  const SimilarityTransform transform = Umeyama(from, to, {}, false);
  if (rms) *rms = RmsDistance(transform, from, to);
  return transform;
}

double RmsDistance(const SimilarityTransform& transform, std::span<const glm::vec3> source,
                   std::span<const glm::vec3> target) {
  double sum = 0.0;
  for (std::size_t i = 0; i < source.size(); ++i) {
    const Eigen::Vector3d moved = transform.scale * (transform.rotation * ToEigen(source[i])) + transform.translation;
    sum += (moved - ToEigen(target[i])).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(source.size()));
}

}  // namespace facerig
