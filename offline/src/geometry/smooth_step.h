// Hermite smooth step: 0 at edge0, 1 at edge1 (either order), smooth between;
// the soft edges of masks, weights and painted regions.
#pragma once

#include <algorithm>

namespace facerig {

inline float SmoothStep(float edge0, float edge1, float x) {
  const float t = std::clamp((x - edge0) / (edge1 - edge0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

}  // namespace facerig
