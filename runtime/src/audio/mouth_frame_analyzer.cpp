#include "audio/mouth_frame_analyzer.h"

#include <algorithm>
#include <cmath>

namespace facerig {
namespace {

struct BandRange {
  double low_hz;
  double high_hz;
};

// Indexed by MouthBand.
constexpr std::array<BandRange, kMouthBandCount> kBandRanges = {{
    {200.0, 600.0}, {600.0, 1100.0}, {1100.0, 1700.0}, {1700.0, 3500.0}, {4000.0, 8000.0}}};

float ToDb(double power) {
  const double db = 10.0 * std::log10(std::max(power, 1e-30));
  return static_cast<float>(std::max(db, double(kMouthSilenceDb)));
}

}  // namespace

MouthFrameAnalyzer::MouthFrameAnalyzer(int sample_rate, std::size_t window_samples)
    : spectrum_(window_samples) {
  const double hz_per_bin = double(sample_rate) / double(spectrum_.fft_size());
  const std::size_t nyquist_bin = spectrum_.fft_size() / 2;
  for (std::size_t b = 0; b < kMouthBandCount; ++b) {
    const auto first = static_cast<std::size_t>(std::ceil(kBandRanges[b].low_hz / hz_per_bin));
    const auto end = static_cast<std::size_t>(std::ceil(kBandRanges[b].high_hz / hz_per_bin));
    band_bins_[b] = {std::min(first, nyquist_bin), std::min(end, nyquist_bin)};
  }
}

MouthFrameFeatures MouthFrameAnalyzer::Analyze(std::span<const float> frame) {
  const std::span<const float> power = spectrum_.Compute(frame);
  const double scale = spectrum_.power_scale();
  MouthFrameFeatures features;
  // One-sided spectrum: every bin but DC and Nyquist stands for two.
  double total = double(power.front()) + double(power.back());
  for (std::size_t k = 1; k + 1 < power.size(); ++k) total += 2.0 * power[k];
  features.level_db = ToDb(total * scale);
  for (std::size_t b = 0; b < kMouthBandCount; ++b) {
    double sum = 0.0;
    for (std::size_t k = band_bins_[b].first; k < band_bins_[b].second; ++k) sum += 2.0 * power[k];
    features.band_db[b] = ToDb(sum * scale);
  }
  return features;
}

std::size_t MouthWindowSamples(int sample_rate, const MouthAnalysisParams& params) {
  return std::max<std::size_t>(2, static_cast<std::size_t>(std::lround(params.window * sample_rate)));
}

}  // namespace facerig
