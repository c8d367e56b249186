// Internal to the offline library: the axis-aligned box around a point set,
// for sizes relative to a mesh (thresholds, grids).
#pragma once

#include <cmath>
#include <span>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace facerig {

struct BoundingBox {
  glm::vec3 low{0.0f};
  glm::vec3 high{0.0f};

  glm::vec3 extent() const { return high - low; }
  float diagonal() const {
    const glm::vec3 d = extent();
    return std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  }
};

// The smallest box holding every position; all zero when there are none.
inline BoundingBox BoxAround(std::span<const glm::vec3> positions) {
  if (positions.empty()) return {};
  BoundingBox box{positions[0], positions[0]};
  for (const glm::vec3& p : positions) {
    box.low = glm::min(box.low, p);
    box.high = glm::max(box.high, p);
  }
  return box;
}

}  // namespace facerig
