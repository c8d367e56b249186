// Delta features: each cepstral coefficient's slope over +-kDeltaReach
// frames, shared by the batch features (audio_features.cpp) and the
// streaming aligner. Private to facerig::runtime.
#pragma once

#include <cstddef>

namespace facerig::detail {

inline constexpr std::size_t kDeltaReach = 2;

// Slopes of `count` coefficients at frame t: `at(k)` gives frame t + k's
// coefficients (k in -kDeltaReach..kDeltaReach, clamped by the caller at the
// ends); `out` receives `count` values. Allocates nothing.
template <typename At>
void DeltasOf(std::size_t count, At at, float* out) {
  float norm = 0.0f;
  for (std::size_t n = 1; n <= kDeltaReach; ++n) norm += 2.0f * static_cast<float>(n * n);
  for (std::size_t c = 0; c < count; ++c) {
    float sum = 0.0f;
    for (std::size_t n = 1; n <= kDeltaReach; ++n) {
      const auto k = static_cast<std::ptrdiff_t>(n);
      sum += static_cast<float>(n) * (at(k)[c] - at(-k)[c]);
    }
    out[c] = sum / norm;
  }
}

}  // namespace facerig::detail
