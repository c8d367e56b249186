// Power spectrum of one audio frame for the audio-only mouth: a Hann window
// (hann_window.h) and a zero-padded radix-2 FFT (fft.h). Private to facerig::runtime.
#pragma once

#include <complex>
#include <cstddef>
#include <span>
#include <vector>

namespace facerig {

class PowerSpectrum {
 public:
  // Sizes every buffer once; `window_samples` >= 2.
  explicit PowerSpectrum(std::size_t window_samples);

  std::size_t window_samples() const { return window_.size(); }
  std::size_t fft_size() const { return buffer_.size(); }

  // Windows `frame` (window_samples() values), transforms it and returns the
  // power of bins 0..fft_size()/2 (bin k is k * sample_rate / fft_size() Hz).
  // Valid until the next call; allocates nothing.
  std::span<const float> Compute(std::span<const float> frame);

  // Scale that turns a sum of Compute()'s bins into mean power: the bins of a
  // whole one-sided spectrum (DC and Nyquist once, the others twice) times
  // this give sum((w x)^2) / sum(w^2), Parseval's theorem for the window w.
  float power_scale() const { return power_scale_; }

 private:
  std::vector<float> window_;
  std::vector<std::complex<float>> buffer_;
  std::vector<float> power_;
  float power_scale_ = 1.0f;
};

}  // namespace facerig
