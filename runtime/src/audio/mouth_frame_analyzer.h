// One frame of audio -> MouthFrameFeatures, shared by the whole-buffer and
// the streaming rough mouth. Private to facerig::runtime.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>

#include "facerig/runtime/audio/mouth_features.h"
#include "audio/power_spectrum.h"

namespace facerig {

class MouthFrameAnalyzer {
 public:
  // `window_samples` >= 2; allocates its buffers once.
  MouthFrameAnalyzer(int sample_rate, std::size_t window_samples);

  std::size_t window_samples() const { return spectrum_.window_samples(); }

  // `frame`: window_samples() samples, full scale +-1. Allocates nothing.
  MouthFrameFeatures Analyze(std::span<const float> frame);

 private:
  PowerSpectrum spectrum_;
  std::array<std::pair<std::size_t, std::size_t>, kMouthBandCount> band_bins_{};  // [first, end)
};

// Window length in samples for these params (>= 2).
std::size_t MouthWindowSamples(int sample_rate, const MouthAnalysisParams& params);

// Samples as full-scale floats; non-finite ones as 0.
inline float MouthSample(float sample) { return std::isfinite(sample) ? sample : 0.0f; }
inline float MouthSample(std::int16_t sample) { return static_cast<float>(sample) / 32768.0f; }

}  // namespace facerig
