// The landmark half of the photo fit as pieces other refinements reuse: the
// landmark term's normal equations with the prior (camera fixed), the bounded
// solve, and the result filled from weights (photo_shape_fit.cpp).
#pragma once

#include <span>
#include <vector>

#include <Eigen/Dense>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/offline/photo/fit.h"

namespace facerig::photo_shape {

// Normal equations of the weighted landmark residuals in the weights
// (identity modes first, then expressions), plus the Gaussian prior.
struct LinearSystem {
  Eigen::MatrixXd normal;
  Eigen::VectorXd rhs;
};

LinearSystem BuildSystem(const PhotoFaceModel& model, const ScaledOrthoCamera& camera,
                         std::span<const glm::vec2> landmarks, std::span<const std::uint32_t> vertices,
                         std::span<const glm::vec2> precisions, int width, int height, const PhotoFitParams& params);

// The solution with the expression weights (after identity_count) kept in [0, 1].
Eigen::VectorXd SolveBounded(const LinearSystem& system, std::size_t identity_count);

// 1 / sigma^2 per landmark and axis, in 1/pixels^2.
std::vector<glm::vec2> LandmarkPrecisions(const PhotoFitParams& params, double face_size);

// The larger side of the landmarks' box, pixels (at least 1).
double FaceSize(std::span<const glm::vec2> landmarks);

// The mode (identity modes first, then expressions) `i` of the model.
const std::vector<glm::vec3>& Mode(const PhotoFaceModel& model, std::size_t i);

// The prior's precision on weight `i`: 1 for an identity mode (unit
// Gaussian), 1 / expression_sigma^2 for an expression.
double PriorPrecision(const PhotoFaceModel& model, const PhotoFitParams& params, std::size_t i);

// Vertices first .. first + count - 1 of the model's shape with the first
// `mode_count` modes at `weights`.
std::vector<glm::vec3> ShapeOf(const PhotoFaceModel& model, const Eigen::VectorXd& weights, std::size_t first,
                               std::size_t count, std::size_t mode_count);

// The mean of `points` (the origin when there are none).
glm::vec3 Centroid(std::span<const glm::vec3> points);

// Weights, rest and posed positions, projections and view of `fit` from
// `weights` (fit.camera and fit.landmark_vertices as they are).
void FillResult(const PhotoFaceModel& model, const Eigen::VectorXd& weights, std::span<const glm::vec2> landmarks,
                int width, int height, PhotoFit& fit);

}  // namespace facerig::photo_shape
