#include "power_spectrum.h"

#include <cmath>
#include <numbers>
#include <utility>

namespace facerig {
namespace {

std::size_t NextPowerOfTwo(std::size_t n) {
  std::size_t size = 1;
  while (size < n) size <<= 1;
  return size;
}

std::size_t ReverseBits(std::size_t index, std::size_t bits) {
  std::size_t reversed = 0;
  for (std::size_t b = 0; b < bits; ++b) {
    reversed = (reversed << 1) | (index & 1);
    index >>= 1;
  }
  return reversed;
}

}  // namespace

PowerSpectrum::PowerSpectrum(std::size_t window_samples)
    : window_(window_samples < 2 ? 2 : window_samples),
      buffer_(NextPowerOfTwo(window_.size())),
      power_(buffer_.size() / 2 + 1) {
  const double two_pi = 2.0 * std::numbers::pi;
  const std::size_t n = window_.size();
  for (std::size_t i = 0; i < n; ++i) {
    window_[i] = static_cast<float>(0.5 - 0.5 * std::cos(two_pi * double(i) / double(n - 1)));
  }
  double window_energy = 0.0;
  for (const float w : window_) window_energy += double(w) * w;
  const std::size_t size = buffer_.size();
  power_scale_ = static_cast<float>(1.0 / (double(size) * window_energy));
  twiddles_.resize(size / 2);
  for (std::size_t k = 0; k < twiddles_.size(); ++k) {
    const double angle = -two_pi * double(k) / double(size);
    twiddles_[k] = {static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle))};
  }
  std::size_t bits = 0;
  while ((std::size_t{1} << bits) < size) ++bits;
  bit_reversed_.resize(size);
  for (std::size_t i = 0; i < size; ++i) bit_reversed_[i] = ReverseBits(i, bits);
}

std::span<const float> PowerSpectrum::Compute(std::span<const float> frame) {
  const std::size_t n = frame.size() < window_.size() ? frame.size() : window_.size();
  for (std::size_t i = 0; i < buffer_.size(); ++i) {
    buffer_[i] = i < n ? std::complex<float>(frame[i] * window_[i], 0.0f) : 0.0f;
  }
  Transform();
  for (std::size_t k = 0; k < power_.size(); ++k) power_[k] = std::norm(buffer_[k]);
  return power_;
}

// Iterative decimation-in-time Cooley-Tukey.
void PowerSpectrum::Transform() {
  const std::size_t size = buffer_.size();
  for (std::size_t i = 0; i < size; ++i) {
    if (i < bit_reversed_[i]) std::swap(buffer_[i], buffer_[bit_reversed_[i]]);
  }
  for (std::size_t half = 1; half < size; half <<= 1) {
    const std::size_t stride = size / (2 * half);
    for (std::size_t start = 0; start < size; start += 2 * half) {
      for (std::size_t k = 0; k < half; ++k) {
        const std::complex<float> odd = twiddles_[k * stride] * buffer_[start + k + half];
        buffer_[start + k + half] = buffer_[start + k] - odd;
        buffer_[start + k] += odd;
      }
    }
  }
}

}  // namespace facerig
