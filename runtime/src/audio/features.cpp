#include "facerig/runtime/audio/features.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <string>

#include "audio/deltas.h"
#include "audio/feature_statistics.h"
#include "audio/fft.h"
#include "audio/hann_window.h"

namespace facerig {
namespace {

// Energies this far below the loudest frame's are treated as equal: digital
// silence (synthetic speech) and a microphone's noise floor then look alike.
constexpr float kEnergyFloorRatio = 1e-7f;
constexpr float kPreEmphasis = 0.97f;

double HzToMel(double hz) { return 1127.0 * std::log1p(hz / 700.0); }
double MelToHz(double mel) { return 700.0 * std::expm1(mel / 1127.0); }

void CheckParams(int sample_rate, const AudioFeatureParams& p) {
  const bool valid = sample_rate > 0 && p.hop_seconds > 0.0 && p.window_seconds >= p.hop_seconds &&
                     p.window_seconds <= 1.0 && p.mel_bands >= 2 && p.mel_bands <= 128 && p.cepstra >= 2 &&
                     p.cepstra <= p.mel_bands && p.low_hz >= 0.0 && p.high_hz > p.low_hz;
  if (!valid) {
    throw std::invalid_argument("ComputeAudioFeatures: bad sample rate (" + std::to_string(sample_rate) +
                                " Hz) or feature parameters");
  }
}

// Triangular mel filters as (first bin, weights) over an FFT's power bins.
struct MelFilter {
  std::size_t first_bin = 0;
  std::vector<float> weights;
};

std::vector<MelFilter> MelFilterBank(const AudioFeatureParams& p, int sample_rate, std::size_t fft_size) {
  const double high_hz = std::min(p.high_hz, 0.5 * sample_rate);
  const double low_mel = HzToMel(std::min(p.low_hz, high_hz * 0.5)), high_mel = HzToMel(high_hz);
  const double bin_hz = static_cast<double>(sample_rate) / static_cast<double>(fft_size);
  std::vector<MelFilter> bank(static_cast<std::size_t>(p.mel_bands));
  for (int band = 0; band < p.mel_bands; ++band) {
    const auto edge = [&](int k) { return MelToHz(low_mel + (high_mel - low_mel) * k / (p.mel_bands + 1)); };
    const double left = edge(band), centre = edge(band + 1), right = edge(band + 2);
    MelFilter& filter = bank[static_cast<std::size_t>(band)];
    filter.first_bin = static_cast<std::size_t>(std::ceil(left / bin_hz));
    for (std::size_t bin = filter.first_bin; static_cast<double>(bin) * bin_hz < right && bin <= fft_size / 2; ++bin) {
      const double hz = static_cast<double>(bin) * bin_hz;
      const double weight = hz < centre ? (hz - left) / (centre - left) : (right - hz) / (right - centre);
      filter.weights.push_back(static_cast<float>(std::max(0.0, weight)));
    }
  }
  return bank;
}

struct Framing {
  int hop = 0, window = 0;
  std::size_t fft_size = 1, frames = 0;
};

Framing MakeFraming(std::size_t sample_count, int sample_rate, const AudioFeatureParams& p) {
  Framing f;
  f.hop = std::max(1, static_cast<int>(std::lround(p.hop_seconds * sample_rate)));
  f.window = std::max(f.hop, static_cast<int>(std::lround(p.window_seconds * sample_rate)));
  while (f.fft_size < static_cast<std::size_t>(f.window)) f.fft_size <<= 1;
  const auto window = static_cast<std::size_t>(f.window), hop = static_cast<std::size_t>(f.hop);
  if (sample_count > 0) f.frames = sample_count <= window ? 1 : 1 + (sample_count - window + hop - 1) / hop;
  return f;
}

// One frame: pre-emphasised, Hann-windowed, transformed; its mel energies
// (linear) go to `mel`, its mean power is returned. `window` may be shorter
// than `hann` (zeros follow); `previous` is the sample before it.
template <typename Filters>
float MelFrame(std::span<const float> window, float previous, std::span<const float> hann,
               std::span<std::complex<float>> buffer, std::span<float> spectrum, const Filters& bank, float* mel) {
  std::fill(buffer.begin(), buffer.end(), std::complex<float>());
  double sum = 0.0;
  for (std::size_t i = 0; i < hann.size(); ++i) {
    const float x = i < window.size() ? window[i] : 0.0f;
    const float before = i == 0 ? previous : (i - 1 < window.size() ? window[i - 1] : 0.0f);
    sum += static_cast<double>(x) * x;
    buffer[i] = hann[i] * (x - kPreEmphasis * before);
  }
  detail::FftInPlace(buffer);
  for (std::size_t bin = 0; bin < spectrum.size(); ++bin) spectrum[bin] = std::norm(buffer[bin]);
  for (std::size_t band = 0; band < bank.size(); ++band) {
    float energy = 0.0f;
    for (std::size_t k = 0; k < bank[band].weights.size(); ++k) {
      energy += bank[band].weights[k] * spectrum[bank[band].first_bin + k];
    }
    mel[band] = energy;
  }
  return static_cast<float>(sum / static_cast<double>(hann.size()));
}

// Mel energies (linear) and mean power of every frame.
void MelEnergies(std::span<const float> samples, const Framing& f, const std::vector<MelFilter>& bank,
                 std::vector<float>& mel, std::vector<float>& power) {
  const std::vector<float> hann = detail::HannWindow(static_cast<std::size_t>(f.window));
  std::vector<std::complex<float>> buffer(f.fft_size);
  std::vector<float> spectrum(f.fft_size / 2 + 1);
  mel.assign(f.frames * bank.size(), 0.0f);
  power.assign(f.frames, 0.0f);
  for (std::size_t frame = 0; frame < f.frames; ++frame) {
    const std::size_t start = frame * static_cast<std::size_t>(f.hop);
    const std::span<const float> window = samples.subspan(start, std::min(hann.size(), samples.size() - start));
    const float previous = start > 0 ? samples[start - 1] : 0.0f;
    power[frame] = MelFrame(window, previous, hann, buffer, spectrum, bank, mel.data() + frame * bank.size());
  }
}

// Log of `values`, floored relative to their maximum.
void FlooredLog(std::vector<float>& values) {
  const float peak = values.empty() ? 0.0f : *std::max_element(values.begin(), values.end());
  const float floor = std::max(peak * kEnergyFloorRatio, 1e-20f);
  for (float& v : values) v = std::log(std::max(v, floor));
}

// Cepstra c1..c(n-1) of each frame's log mel energies, with the log energy as the first value.
void Cepstra(const std::vector<float>& log_mel, const std::vector<float>& log_energy, std::size_t bands,
             int cepstra, int dimension, std::vector<float>& out) {
  const std::size_t frames = log_energy.size();
  const auto band_count = static_cast<double>(bands);
  for (std::size_t frame = 0; frame < frames; ++frame) {
    float* row = out.data() + frame * static_cast<std::size_t>(dimension);
    row[0] = log_energy[frame];
    for (int c = 1; c < cepstra; ++c) {
      double sum = 0.0;
      for (std::size_t band = 0; band < bands; ++band) {
        sum += log_mel[frame * bands + band] * std::cos(std::numbers::pi * c * (static_cast<double>(band) + 0.5) / band_count);
      }
      row[c] = static_cast<float>(sum * std::sqrt(2.0 / band_count));
    }
  }
}

void Deltas(std::size_t frames, int cepstra, int dimension, std::vector<float>& values) {
  const auto row = [&](std::ptrdiff_t frame) {
    frame = std::clamp<std::ptrdiff_t>(frame, 0, static_cast<std::ptrdiff_t>(frames) - 1);
    return values.data() + static_cast<std::size_t>(frame) * static_cast<std::size_t>(dimension);
  };
  for (std::size_t frame = 0; frame < frames; ++frame) {
    const auto t = static_cast<std::ptrdiff_t>(frame);
    detail::DeltasOf(static_cast<std::size_t>(cepstra), [&](std::ptrdiff_t k) { return row(t + k); }, row(t) + cepstra);
  }
}

// Zero mean and unit variance per dimension over all frames.
void NormalizeMeanVariance(int dimension, std::vector<float>& values) {
  const auto n = static_cast<std::size_t>(dimension);
  for (std::size_t d = 0; d < n; ++d) detail::Normalize(values, n, d, detail::StatisticsOf(values, n, d));
}

}  // namespace

AudioFeatures ComputeAudioFeatures(std::span<const float> samples, int sample_rate, const AudioFeatureParams& params) {
  CheckParams(sample_rate, params);
  const Framing framing = MakeFraming(samples.size(), sample_rate, params);
  AudioFeatures features;
  features.sample_rate = sample_rate;
  features.hop_samples = framing.hop;
  features.window_samples = framing.window;
  features.dimension = params.deltas ? 2 * params.cepstra : params.cepstra;
  if (framing.frames == 0) return features;
  const std::vector<MelFilter> bank = MelFilterBank(params, sample_rate, framing.fft_size);
  std::vector<float> mel;
  MelEnergies(samples, framing, bank, mel, features.log_energy);
  FlooredLog(mel);
  FlooredLog(features.log_energy);
  features.values.assign(framing.frames * static_cast<std::size_t>(features.dimension), 0.0f);
  Cepstra(mel, features.log_energy, bank.size(), params.cepstra, features.dimension, features.values);
  if (params.deltas) Deltas(framing.frames, params.cepstra, features.dimension, features.values);
  NormalizeMeanVariance(features.dimension, features.values);
  return features;
}

FrameCepstra::FrameCepstra(int sample_rate, const AudioFeatureParams& params) {
  CheckParams(sample_rate, params);
  const Framing framing = MakeFraming(0, sample_rate, params);
  hop_ = framing.hop;
  cepstra_ = params.cepstra;
  hann_ = detail::HannWindow(static_cast<std::size_t>(framing.window));
  for (MelFilter& filter : MelFilterBank(params, sample_rate, framing.fft_size)) {
    bank_.push_back({filter.first_bin, std::move(filter.weights)});
  }
  const auto bands = static_cast<double>(bank_.size());
  for (int c = 0; c < cepstra_; ++c) {
    for (std::size_t band = 0; band < bank_.size(); ++band) {
      cosines_.push_back(static_cast<float>(std::cos(std::numbers::pi * c * (static_cast<double>(band) + 0.5) / bands) *
                                            std::sqrt(2.0 / bands)));
    }
  }
  buffer_.resize(framing.fft_size);
  spectrum_.resize(framing.fft_size / 2 + 1);
  log_mel_.resize(bank_.size());
}

void FrameCepstra::Compute(std::span<const float> window, float previous, std::span<float> out) {
  // Fixed floors: -100 dB of full-scale power for the energy, as low for the bands.
  constexpr float kPowerFloor = 1e-10f, kBandFloor = 1e-10f;
  const float power = MelFrame(window, previous, hann_, buffer_, spectrum_, bank_, log_mel_.data());
  for (float& energy : log_mel_) energy = std::log(std::max(energy, kBandFloor));
  out[0] = std::log(std::max(power, kPowerFloor));
  for (int c = 1; c < cepstra_; ++c) {
    float value = 0.0f;
    for (std::size_t band = 0; band < bank_.size(); ++band) {
      value += log_mel_[band] * cosines_[static_cast<std::size_t>(c) * bank_.size() + band];
    }
    out[static_cast<std::size_t>(c)] = value;
  }
}

std::vector<float> PcmToFloat(std::span<const std::int16_t> samples) {
  std::vector<float> out(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) out[i] = static_cast<float>(samples[i]) / 32768.0f;
  return out;
}

}  // namespace facerig
