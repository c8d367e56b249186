#include "facerig/runtime/speech/audio_mouth_features.h"

#include <algorithm>
#include <cmath>

#include "power_spectrum.h"

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

float ToFloat(float sample) { return std::isfinite(sample) ? sample : 0.0f; }
float ToFloat(std::int16_t sample) { return static_cast<float>(sample) / 32768.0f; }

bool ValidParams(int sample_rate, const MouthAnalysisParams& params) {
  return sample_rate >= kMouthMinSampleRate && sample_rate <= kMouthMaxSampleRate &&
         std::isfinite(params.hop) && std::isfinite(params.window) && params.hop > 0.0 &&
         params.window >= params.hop && params.window <= 1.0;
}

// Bin ranges [first, last) of the bands at this rate and FFT size.
std::array<std::pair<std::size_t, std::size_t>, kMouthBandCount> BandBins(int sample_rate,
                                                                          std::size_t fft_size) {
  std::array<std::pair<std::size_t, std::size_t>, kMouthBandCount> bins{};
  const double hz_per_bin = double(sample_rate) / double(fft_size);
  const std::size_t last_bin = fft_size / 2;  // Nyquist
  for (std::size_t b = 0; b < kMouthBandCount; ++b) {
    const auto first = static_cast<std::size_t>(std::ceil(kBandRanges[b].low_hz / hz_per_bin));
    const auto end = static_cast<std::size_t>(std::ceil(kBandRanges[b].high_hz / hz_per_bin));
    bins[b] = {std::min(first, last_bin), std::min(end, last_bin)};
  }
  return bins;
}

MouthFrameFeatures FrameFeatures(std::span<const float> power, float scale,
                                 const std::array<std::pair<std::size_t, std::size_t>,
                                                  kMouthBandCount>& bands) {
  MouthFrameFeatures features;
  // One-sided spectrum: every bin but DC and Nyquist stands for two.
  double total = double(power.front()) + double(power.back());
  for (std::size_t k = 1; k + 1 < power.size(); ++k) total += 2.0 * power[k];
  features.level_db = ToDb(total * scale);
  for (std::size_t b = 0; b < kMouthBandCount; ++b) {
    double sum = 0.0;
    for (std::size_t k = bands[b].first; k < bands[b].second; ++k) sum += 2.0 * power[k];
    features.band_db[b] = ToDb(sum * scale);
  }
  return features;
}

template <typename Sample>
std::vector<MouthFrameFeatures> Analyze(std::span<const Sample> samples, int sample_rate,
                                        const MouthAnalysisParams& params) {
  std::vector<MouthFrameFeatures> frames;
  const std::size_t hop = MouthHopSamples(sample_rate, params);
  if (hop == 0 || samples.empty()) return frames;
  const auto window = std::max<std::size_t>(
      2, static_cast<std::size_t>(std::lround(params.window * sample_rate)));
  PowerSpectrum spectrum(window);
  const auto bands = BandBins(sample_rate, spectrum.fft_size());
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
      frame[j] = at >= 0 && at < size ? ToFloat(samples[static_cast<std::size_t>(at)]) : 0.0f;
    }
    frames.push_back(FrameFeatures(spectrum.Compute(frame), spectrum.power_scale(), bands));
  }
  return frames;
}

}  // namespace

std::size_t MouthHopSamples(int sample_rate, const MouthAnalysisParams& params) {
  if (!ValidParams(sample_rate, params)) return 0;
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
