// The audio-visual sync measure itself (tests/support/av_sync.h) on signals
// with a known answer: a mouth series that is the sound's envelope shifted,
// a silence inside noise, a moving box in still frames.
#include "measure/av_sync.h"

#include <cmath>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

namespace facerig::test {
namespace {

// Noise whose loudness rises and falls like syllables (about 4 per second).
std::vector<float> SyllableNoise(int rate, double seconds) {
  std::mt19937 random(7);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  std::vector<float> samples(static_cast<std::size_t>(rate * seconds));
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double t = static_cast<double>(i) / rate;
    const double loudness = std::pow(std::sin(3.1 * 3.14159265 * t) * std::sin(1.3 * t + 0.4), 2.0);
    samples[i] = static_cast<float>(0.3 * loudness) * noise(random);
  }
  return samples;
}

TEST_CASE("av_sync: the lag of a mouth series that follows the envelope by 37 ms", "[demo][av-sync]") {
  constexpr int kRate = 16000;
  constexpr double kFps = 100.0;
  const std::vector<float> sound = SyllableNoise(kRate, 4.0);
  const std::vector<double> envelope = RmsEnvelope(sound, kRate, 1.0 / kFps, 1.0 / kFps);
  for (const double shift : {0.0, 0.037, -0.052}) {
    // Frame i shows the envelope at i / fps - shift, interpolated on a 1 ms grid first.
    const std::vector<double> fine = RmsEnvelope(sound, kRate, 0.001, 1.0 / kFps);
    std::vector<double> mouth;
    for (std::size_t i = 0; i < envelope.size(); ++i) {
      const long at = std::lround(1000.0 * (static_cast<double>(i) / kFps - shift));
      mouth.push_back(fine[static_cast<std::size_t>(std::clamp(at, 0L, static_cast<long>(fine.size()) - 1))]);
    }
    const LagPeak lag = MouthLag(mouth, kFps, sound, kRate);
    INFO("shift " << shift << " s, measured " << lag.lag_seconds << " s, r " << lag.correlation);
    CHECK(lag.lag_seconds == Approx(shift).margin(0.003));
    CHECK(lag.correlation > 0.9);
  }
}

TEST_CASE("av_sync: the quietest window finds a 40 ms silence in noise", "[demo][av-sync]") {
  constexpr int kRate = 16000;
  std::vector<float> sound = SyllableNoise(kRate, 1.0);
  for (float& s : sound) s += 0.05f;  // no silence of its own
  for (std::size_t i = 9600; i < 9600 + 640; ++i) sound[i] = 0.0f;  // 0.600-0.640 s
  CHECK(QuietestWindow(sound, kRate, 0.4, 0.8, 0.030) == Approx(0.605).margin(0.006));
  CHECK(QuietestWindow(sound, kRate, 0.0, 0.3, 0.030) < 0.3);  // searched only in the range
}

TEST_CASE("av_sync: the changing box is found in the lower half, a blink above is left out", "[demo][av-sync]") {
  std::vector<FramePixels> frames(3, FramePixels{40, 30, 3, std::vector<std::uint8_t>(40 * 30 * 3, 100)});
  const auto paint = [](FramePixels& f, int x0, int y0, int x1, int y1, std::uint8_t value) {
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) {
        for (int c = 0; c < 3; ++c) f.values[(static_cast<std::size_t>(y) * f.width + x) * 3 + c] = value;
      }
    }
  };
  paint(frames[1], 15, 20, 25, 24, 20);  // the mouth opens
  paint(frames[2], 15, 20, 25, 22, 20);  // half as far
  paint(frames[2], 5, 5, 12, 8, 0);      // a blink
  const PixelBox box = ChangingLowerBox(frames);
  CHECK(box.x0 == 15);
  CHECK(box.x1 == 25);
  CHECK(box.y0 == 20);
  CHECK(box.y1 == 24);
  const std::vector<double> series = MouthSeries(frames, box);
  REQUIRE(series.size() == 3);
  CHECK(series[0] == 0.0);
  CHECK(series[1] == Approx(80.0));
  CHECK(series[2] == Approx(40.0));
}

}  // namespace
}  // namespace facerig::test
