#include "facerig/runtime/audio/mouth_features.h"

#include <algorithm>
#include <cmath>

#include "audio/mouth_frame_analyzer.h"

namespace facerig {
namespace {

template <typename Sample>
std::vector<MouthFrameFeatures> Analyze(std::span<const Sample> samples, int sample_rate,
                                        const MouthAnalysisParams& params) {
  std::vector<MouthFrameFeatures> frames;
  const std::size_t hop = MouthHopSamples(sample_rate, params);
  if (hop == 0 || samples.empty()) return frames;
  MouthFrameAnalyzer analyzer(sample_rate, MouthWindowSamples(sample_rate, params));
  const std::size_t window = analyzer.window_samples();
  std::vector<float> frame(window);
  const std::size_t count = (samples.size() + hop - 1) / hop;
  frames.reserve(count);
  const auto half = static_cast<std::ptrdiff_t>(window / 2);
  const auto size = static_cast<std::ptrdiff_t>(samples.size());
  for (std::size_t i = 0; i < count; ++i) {
    // Centred on sample i * hop, zero outside the buffer.
    const std::ptrdiff_t first = static_cast<std::ptrdiff_t>(i * hop) - half;
    for (std::size_t j = 0; j < window; ++j) {
      const std::ptrdiff_t at = first + static_cast<std::ptrdiff_t>(j);
      frame[j] = at >= 0 && at < size ? MouthSample(samples[static_cast<std::size_t>(at)]) : 0.0f;
    }
    frames.push_back(analyzer.Analyze(frame));
  }
  return frames;
}

}  // namespace

std::size_t MouthHopSamples(int sample_rate, const MouthAnalysisParams& params) {
  const bool valid = sample_rate >= kMouthMinSampleRate && sample_rate <= kMouthMaxSampleRate &&
                     std::isfinite(params.hop) && std::isfinite(params.window) && params.hop > 0.0 &&
                     params.window >= params.hop && params.window <= 1.0;
  if (!valid) return 0;
  return std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(params.hop * sample_rate)));
}

std::vector<MouthFrameFeatures> AnalyzeMouthFrames(std::span<const float> samples,
                                                   int sample_rate,
                                                   const MouthAnalysisParams& params) {
  return Analyze(samples, sample_rate, params);
}

std::vector<MouthFrameFeatures> AnalyzeMouthFrames(std::span<const std::int16_t> samples,
                                                   int sample_rate,
                                                   const MouthAnalysisParams& params) {
  return Analyze(samples, sample_rate, params);
}

}  // namespace facerig
