// Similarity transforms (scale, rotation, translation) and the least-squares
// fit of one to point pairs. x_target = scale * rotation * x_source + translation.
#pragma once

#include <cstdint>
#include <span>

#include <Eigen/Core>
#include <glm/vec3.hpp>

namespace facerig {

struct SimilarityTransform {
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  glm::vec3 Apply(glm::vec3 p) const;
  // Rotation only (directions, normals).
  glm::vec3 ApplyToDirection(glm::vec3 d) const;
  SimilarityTransform Inverse() const;
  // (this * other)(x) = this(other(x)).
  SimilarityTransform operator*(const SimilarityTransform& other) const;
};

// Least-squares similarity (or rigid, when !with_scale) transform mapping
// `source[i]` onto `target[i]` (Umeyama 1991), optionally weighted: the one
// closed-form fit of the project (Eigen::umeyama has no weights, which the
// landmark confidences need).
// \pre source.size() == target.size() >= 3, weights empty or the same size.
// \throw InvalidInputError on mismatched sizes, fewer than 3 points with
//        positive weight, non-finite input, or all points coincident.
SimilarityTransform Umeyama(std::span<const glm::vec3> source, std::span<const glm::vec3> target,
                            std::span<const float> weights = {}, bool with_scale = true);

// Rigid fit (Umeyama without scale) of moving[v] onto fixed[v] for the
// vertices in `subset` (empty: all). rms (if given): the fit's residual.
// \throw InvalidInputError on mismatched sizes, an index out of range or
//        fewer than 3 points.
SimilarityTransform FitRigid(std::span<const glm::vec3> moving, std::span<const glm::vec3> fixed,
                             std::span<const std::uint32_t> subset = {}, double* rms = nullptr);

// Root-mean-square distance between transform(source[i]) and target[i].
// \pre source.size() == target.size() > 0.
double RmsDistance(const SimilarityTransform& transform, std::span<const glm::vec3> source,
                   std::span<const glm::vec3> target);

}  // namespace facerig
