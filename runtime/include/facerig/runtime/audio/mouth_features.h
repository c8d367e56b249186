// Audio-only mouth, step 1 of 3: per-frame loudness and spectral shape of a
// mono recording (see audio_mouth.h for the whole rough mode).
//
// Frame i is centred on time i * hop (the signal is zero outside the buffer)
// and stands for [i*hop - hop/2, i*hop + hop/2]. All levels are in dB of mean
// power (a full-scale square wave is 0 dB); band levels are spectral powers
// summed over the band's bins, so only their differences are meaningful.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace facerig {

// The spectral bands the mouth classes are told apart by, in Hz.
enum class MouthBand : std::uint8_t {
  kLowFormant,   // 200-600: first formant of closed vowels (i, u), nasal murmur
  kHighFormant,  // 600-1100: first formant of open vowels (a)
  kBackFormant,  // 1100-1700: second formant of back and open vowels
  kFrontFormant, // 1700-3500: second/third formant of front vowels (i, e)
  kFrication,    // 4000-8000: sibilants and other fricatives
};
inline constexpr std::size_t kMouthBandCount = 5;

struct MouthFrameFeatures {
  float level_db = 0.0f;  // frame loudness (window-weighted mean power)
  // Per MouthBand; bands above the Nyquist frequency are the silence level.
  std::array<float, kMouthBandCount> band_db{};

  float band(MouthBand b) const { return band_db[static_cast<std::size_t>(b)]; }
};

struct MouthAnalysisParams {
  double hop = 0.010;     // seconds between frames
  double window = 0.025;  // analysis window length, seconds (>= hop)
};

// The level given to digital silence (and the floor of every level).
inline constexpr float kMouthSilenceDb = -120.0f;

// Lowest and highest sample rates analysed, Hz.
inline constexpr int kMouthMinSampleRate = 4000;
inline constexpr int kMouthMaxSampleRate = 384000;

// One entry per frame: ceil(samples.size() / hop) frames. Empty when the
// sample rate is outside [kMouthMinSampleRate, kMouthMaxSampleRate], the
// params are not finite and positive, or there are no samples. Float samples
// are full scale at +-1; int16 at +-32768. Non-finite samples count as 0.
std::vector<MouthFrameFeatures> AnalyzeMouthFrames(std::span<const float> samples,
                                                   int sample_rate,
                                                   const MouthAnalysisParams& params = {});
std::vector<MouthFrameFeatures> AnalyzeMouthFrames(std::span<const std::int16_t> samples,
                                                   int sample_rate,
                                                   const MouthAnalysisParams& params = {});

// Frames of `params.hop` at `sample_rate` (at least 1 sample), or 0 for bad params.
std::size_t MouthHopSamples(int sample_rate, const MouthAnalysisParams& params);

}  // namespace facerig
