// The range check the runtime's parameter validations (audio clock, blinks) share.
#pragma once

#include <cmath>

namespace facerig {

// Whether x is a finite number in [lo, hi] (NaN and infinities are not).
inline bool InRange(double x, double lo, double hi) { return std::isfinite(x) && x >= lo && x <= hi; }

}  // namespace facerig
