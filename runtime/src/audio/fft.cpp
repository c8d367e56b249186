#include "audio/fft.h"

#include <cmath>
#include <numbers>
#include <utility>

namespace facerig::detail {

void FftInPlace(std::span<std::complex<float>> values) {
  const std::size_t n = values.size();
  for (std::size_t i = 1, j = 0; i < n; ++i) {  // bit-reversal permutation
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(values[i], values[j]);
  }
  for (std::size_t length = 2; length <= n; length <<= 1) {
    const double angle = -2.0 * std::numbers::pi / static_cast<double>(length);
    const std::complex<float> step(static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle)));
    for (std::size_t start = 0; start < n; start += length) {
      std::complex<float> twiddle(1.0f, 0.0f);
      for (std::size_t k = 0; k < length / 2; ++k) {
        const std::complex<float> even = values[start + k];
        const std::complex<float> odd = values[start + k + length / 2] * twiddle;
        values[start + k] = even + odd;
        values[start + k + length / 2] = even - odd;
        twiddle *= step;
      }
    }
  }
}

}  // namespace facerig::detail
