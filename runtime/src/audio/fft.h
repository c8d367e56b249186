// In-place radix-2 FFT for every per-frame spectrum of speech (the alignment
// features, the audio-only mouth): the runtime core has no FFT library, and a
// few hundred points per frame need no more. Allocates nothing.
#pragma once

#include <complex>
#include <span>

namespace facerig::detail {

// Forward transform of `values`, whose size must be a power of two.
void FftInPlace(std::span<std::complex<float>> values);

}  // namespace facerig::detail
