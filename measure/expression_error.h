// How well a transfer matches a known answer: the error measures the transfer
// tests and `facerig-bench transfer` report for one expression.
#pragma once

#include <cstddef>
#include <span>

#include <glm/vec3.hpp>

namespace facerig {

// Issue 6's metrics for one expression on a same-topology target, over the
// vertices [region_first, region_last) (ICT: the face, 0-9408).
// moved: region vertices whose true displacement exceeds moved_fraction of the
// largest true displacement in the region; still: below still_fraction.
struct ExpressionError {
  double relative_error = 0.0;  // mean |result - truth| / mean |truth - rest|, over moved
  double leak = 0.0;            // mean |result - rest| over still / mean |truth - rest| over moved
  double max_error = 0.0;       // largest |result - truth| over the region, mesh units
  std::size_t moved_vertices = 0;
  std::size_t still_vertices = 0;
};
// rest, truth, result: #V each. \throw MeshInputError on size mismatch.
ExpressionError MeasureExpressionError(std::span<const glm::vec3> rest,
                                       std::span<const glm::vec3> truth,
                                       std::span<const glm::vec3> result,
                                       std::size_t region_first, std::size_t region_last,
                                       double moved_fraction = 0.1, double still_fraction = 0.01);

}  // namespace facerig
