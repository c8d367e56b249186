#include "facerig/runtime/audio/features.h"

#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "support/test_audio.h"

namespace facerig {
namespace {

TEST_CASE("ComputeAudioFeatures: 10 ms frames, normalised per dimension", "[audio_features]") {
  std::vector<float> audio = test::Sine(300.0, 0.5, 16000);
  const std::vector<float> high = test::Sine(2500.0, 0.5, 16000, 0.1f);
  audio.insert(audio.end(), high.begin(), high.end());
  const AudioFeatures features = ComputeAudioFeatures(audio, 16000);
  CHECK(features.hop_samples == 160);
  CHECK(features.window_samples == 400);
  CHECK(features.dimension == 12);
  CHECK(features.frame_count() == 1 + (16000 - 400 + 159) / 160);
  CHECK(features.FrameTime(0) == Approx(0.0125));
  CHECK(features.FrameTime(10) == Approx(0.1125));
  for (int d = 0; d < features.dimension; ++d) {
    double sum = 0.0, squares = 0.0;
    for (std::size_t f = 0; f < features.frame_count(); ++f) {
      sum += features.frame(f)[static_cast<std::size_t>(d)];
      squares += std::pow(features.frame(f)[static_cast<std::size_t>(d)], 2.0);
    }
    const auto frames = static_cast<double>(features.frame_count());
    CHECK(sum / frames == Approx(0.0).margin(1e-4));
    CHECK(squares / frames == Approx(1.0).margin(1e-3));
  }
  // The two halves differ; frames inside one half agree.
  const auto distance = [&](std::size_t a, std::size_t b) {
    double sum = 0.0;
    for (std::size_t k = 0; k < static_cast<std::size_t>(features.dimension); ++k) {
      sum += std::pow(features.frame(a)[k] - features.frame(b)[k], 2.0);
    }
    return std::sqrt(sum);
  };
  CHECK(distance(10, 30) < 0.2 * distance(10, 70));
  CHECK(features.log_energy[10] > features.log_energy[70]);
}

TEST_CASE("ComputeAudioFeatures: empty, short and silent audio, bad params", "[audio_features]") {
  CHECK(ComputeAudioFeatures({}, 16000).frame_count() == 0);
  const std::vector<float> short_audio(100, 0.1f);
  CHECK(ComputeAudioFeatures(short_audio, 16000).frame_count() == 1);
  const std::vector<float> silence(16000, 0.0f);
  const AudioFeatures quiet = ComputeAudioFeatures(silence, 16000);
  for (float v : quiet.values) CHECK(std::isfinite(v));
  CHECK_THROWS_AS(ComputeAudioFeatures(silence, 0), std::invalid_argument);
  AudioFeatureParams bad;
  bad.cepstra = 40;
  CHECK_THROWS_AS(ComputeAudioFeatures(silence, 16000, bad), std::invalid_argument);
}

TEST_CASE("PcmToFloat: full scale maps into -1 (inclusive) to 1 (exclusive)", "[audio_features]") {
  const std::vector<std::int16_t> pcm = {-32768, 0, 16384};
  CHECK(PcmToFloat(pcm) == std::vector<float>{-1.0f, 0.0f, 0.5f});
}

}  // namespace
}  // namespace facerig
