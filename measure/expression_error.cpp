#include "measure/expression_error.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "facerig/offline/error.h"

namespace facerig {

ExpressionError MeasureExpressionError(std::span<const glm::vec3> rest,
                                       std::span<const glm::vec3> truth,
                                       std::span<const glm::vec3> result,
                                       std::size_t region_first, std::size_t region_last,
                                       double moved_fraction, double still_fraction) {
  if (truth.size() != rest.size()) throw MeshInputError("truth", "vertex count differs from rest");
  if (result.size() != rest.size()) {
    throw MeshInputError("result", "vertex count differs from rest");
  }
  region_last = std::min(region_last, rest.size());
  ExpressionError error;
  if (region_first >= region_last) return error;
  double largest = 0.0;
  for (std::size_t v = region_first; v < region_last; ++v) {
    largest = std::max(largest, static_cast<double>(glm::length(truth[v] - rest[v])));
  }
  double moved_truth = 0.0;
  double moved_error = 0.0;
  double still_motion = 0.0;
  for (std::size_t v = region_first; v < region_last; ++v) {
    const double motion = glm::length(truth[v] - rest[v]);
    const double err = glm::length(result[v] - truth[v]);
    error.max_error = std::max(error.max_error, err);
    if (motion > moved_fraction * largest) {
      moved_truth += motion;
      moved_error += err;
      ++error.moved_vertices;
    } else if (motion < still_fraction * largest) {
      still_motion += glm::length(result[v] - rest[v]);
      ++error.still_vertices;
    }
  }
  if (error.moved_vertices == 0 || !(moved_truth > 0.0)) return error;
  const double mean_truth = moved_truth / static_cast<double>(error.moved_vertices);
  error.relative_error = moved_error / static_cast<double>(error.moved_vertices) / mean_truth;
  if (error.still_vertices > 0) {
    error.leak = still_motion / static_cast<double>(error.still_vertices) / mean_truth;
  }
  return error;
}

}  // namespace facerig
