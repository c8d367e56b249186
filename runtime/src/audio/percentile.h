// The value at a share of a set of levels, for the loudness thresholds of the
// aligners and the audio-only mouth. Private to facerig::runtime.
#pragma once

#include <span>

namespace facerig::detail {

// The value at `share` (0..1) of the sorted `values` (the lower neighbour
// of a fractional rank); reorders them. `values` must not be empty.
float PercentileInPlace(std::span<float> values, double share);

}  // namespace facerig::detail
