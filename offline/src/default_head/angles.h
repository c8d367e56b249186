// Angles of the built-in head's sculpting code, which states them in degrees.
#pragma once

#include <numbers>

namespace facerig::default_head {

inline constexpr double kPi = std::numbers::pi;

inline double Radians(double degrees) { return degrees * kPi / 180.0; }

}  // namespace facerig::default_head
