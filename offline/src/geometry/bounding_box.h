// Internal to the offline library: the axis-aligned box around a point set,
// for sizes relative to a mesh (thresholds, grids) or to a face in a photo.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace facerig {

// Point: glm::vec3 (meshes) or glm::vec2 (pixels).
template <typename Point>
struct Box {
  Point low{0.0f};
  Point high{0.0f};

  Point extent() const { return high - low; }
  Point centre() const { return 0.5f * (low + high); }
  float diagonal() const { return glm::length(extent()); }
};

using BoundingBox = Box<glm::vec3>;
using PixelBox = Box<glm::vec2>;

// The smallest box holding every point; all zero when there are none.
template <typename Point>
Box<Point> BoxAround(std::span<const Point> points) {
  if (points.empty()) return {};
  Box<Point> box{points[0], points[0]};
  for (const Point& p : points) {
    box.low = glm::min(box.low, p);
    box.high = glm::max(box.high, p);
  }
  return box;
}

inline BoundingBox BoxAround(std::span<const glm::vec3> points) { return BoxAround<glm::vec3>(points); }
inline PixelBox BoxAround(std::span<const glm::vec2> points) { return BoxAround<glm::vec2>(points); }

// The box around the points named by `subset`; all zero when it is empty.
inline BoundingBox BoxAround(std::span<const glm::vec3> points, std::span<const std::uint32_t> subset) {
  if (subset.empty()) return {};
  BoundingBox box{points[subset[0]], points[subset[0]]};
  for (const std::uint32_t v : subset) {
    box.low = glm::min(box.low, points[v]);
    box.high = glm::max(box.high, points[v]);
  }
  return box;
}

}  // namespace facerig
