#include "audio/power_spectrum.h"

#include "audio/fft.h"
#include "audio/hann_window.h"

namespace facerig {
namespace {

std::size_t NextPowerOfTwo(std::size_t n) {
  std::size_t size = 1;
  while (size < n) size <<= 1;
  return size;
}

}  // namespace

PowerSpectrum::PowerSpectrum(std::size_t window_samples)
    : window_(detail::HannWindow(window_samples < 2 ? 2 : window_samples)),
      buffer_(NextPowerOfTwo(window_.size())),
      power_(buffer_.size() / 2 + 1) {
  double window_energy = 0.0;
  for (const float w : window_) window_energy += double(w) * w;
  power_scale_ = static_cast<float>(1.0 / (double(buffer_.size()) * window_energy));
}

std::span<const float> PowerSpectrum::Compute(std::span<const float> frame) {
  const std::size_t n = frame.size() < window_.size() ? frame.size() : window_.size();
  for (std::size_t i = 0; i < buffer_.size(); ++i) {
    buffer_[i] = i < n ? std::complex<float>(frame[i] * window_[i], 0.0f) : 0.0f;
  }
  detail::FftInPlace(buffer_);
  for (std::size_t k = 0; k < power_.size(); ++k) power_[k] = std::norm(buffer_[k]);
  return power_;
}

}  // namespace facerig
