// A colour channel in [0, 1] as the byte a texture stores (clamped, rounded).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace facerig {

inline std::uint8_t ToByte(float unit) { return static_cast<std::uint8_t>(std::lround(255.0f * std::clamp(unit, 0.0f, 1.0f))); }

}  // namespace facerig
