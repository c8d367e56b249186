#include "facerig/runtime/audio/mouth_features.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include <catch2/catch.hpp>

#include "support/test_audio.h"

namespace facerig {
namespace {

using test::kSpeechRate;

std::vector<float> Sine(double hz, double seconds, float amplitude) {
  std::vector<float> out(static_cast<std::size_t>(seconds * kSpeechRate));
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = amplitude * static_cast<float>(std::sin(2.0 * std::numbers::pi * hz * double(i) / kSpeechRate));
  }
  return out;
}

TEST_CASE("audio mouth features: a sine's level and band", "[audio_mouth]") {
  const std::vector<float> sine = Sine(800.0, 0.5, 1.0f);
  const std::vector<MouthFrameFeatures> frames = AnalyzeMouthFrames(sine, kSpeechRate);
  // One frame per 10 ms hop, rounded up.
  REQUIRE(frames.size() == 50);
  const MouthFrameFeatures& f = frames[25];
  CHECK(f.level_db == Approx(-3.01).margin(0.1));  // mean power 1/2
  CHECK(f.band(MouthBand::kHighFormant) == Approx(-3.01).margin(0.2));
  for (MouthBand other : {MouthBand::kLowFormant, MouthBand::kFrontFormant, MouthBand::kFrication}) {
    CHECK(f.band(other) < f.level_db - 30.0f);
  }
  // The first frame is centred on sample 0: half of its window is outside the buffer.
  CHECK(frames.front().level_db < f.level_db - 1.0f);
}

TEST_CASE("audio mouth features: silence, int16 and bad samples", "[audio_mouth]") {
  const std::vector<float> silence(1600, 0.0f);
  for (const MouthFrameFeatures& f : AnalyzeMouthFrames(silence, kSpeechRate)) {
    CHECK(f.level_db == kMouthSilenceDb);
    CHECK(f.band(MouthBand::kFrication) == kMouthSilenceDb);
  }
  const std::vector<float> sine = Sine(3000.0, 0.1, 0.5f);
  std::vector<std::int16_t> pcm(sine.size());
  for (std::size_t i = 0; i < sine.size(); ++i) pcm[i] = static_cast<std::int16_t>(std::lround(sine[i] * 32768.0f));
  const auto from_float = AnalyzeMouthFrames(sine, kSpeechRate);
  const auto from_int = AnalyzeMouthFrames(pcm, kSpeechRate);
  REQUIRE(from_float.size() == from_int.size());
  for (std::size_t i = 0; i < from_float.size(); ++i) {
    CHECK(from_int[i].level_db == Approx(from_float[i].level_db).margin(0.01));
    CHECK(from_int[i].band(MouthBand::kFrontFormant) ==
          Approx(from_float[i].band(MouthBand::kFrontFormant)).margin(0.01));
  }
  // Non-finite samples count as silence.
  std::vector<float> bad(1600, std::numeric_limits<float>::quiet_NaN());
  bad[10] = std::numeric_limits<float>::infinity();
  for (const MouthFrameFeatures& f : AnalyzeMouthFrames(bad, kSpeechRate)) CHECK(f.level_db == kMouthSilenceDb);
}

TEST_CASE("audio mouth features: invalid inputs give no frames", "[audio_mouth]") {
  const std::vector<float> sine = Sine(500.0, 0.1, 0.5f);
  CHECK(AnalyzeMouthFrames(sine, 0).empty());
  CHECK(AnalyzeMouthFrames(sine, kMouthMinSampleRate - 1).empty());
  CHECK(AnalyzeMouthFrames(sine, kMouthMaxSampleRate + 1).empty());
  CHECK(AnalyzeMouthFrames(std::span<const float>(), kSpeechRate).empty());
  MouthAnalysisParams params;
  params.hop = std::numeric_limits<double>::quiet_NaN();
  CHECK(AnalyzeMouthFrames(sine, kSpeechRate, params).empty());
  params.hop = 0.02;
  params.window = 0.01;  // shorter than the hop
  CHECK(AnalyzeMouthFrames(sine, kSpeechRate, params).empty());
  CHECK(MouthHopSamples(kSpeechRate, params) == 0);
  // Bands above the Nyquist frequency hold the silence level (8 kHz audio has no frication band).
  const std::vector<MouthFrameFeatures> narrow = AnalyzeMouthFrames(Sine(500.0, 0.1, 0.5f), 8000);
  REQUIRE_FALSE(narrow.empty());
  CHECK(narrow[5].band(MouthBand::kFrication) == kMouthSilenceDb);
}

}  // namespace
}  // namespace facerig
