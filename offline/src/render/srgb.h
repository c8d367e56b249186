// Linear light to the sRGB encoding (IEC 61966-2-1) that PNG textures and
// previews painted in code store.
#pragma once

#include <cmath>

namespace facerig {

inline float LinearToSrgb(float linear) {
  return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

}  // namespace facerig
