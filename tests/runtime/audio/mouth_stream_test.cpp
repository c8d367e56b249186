#include "facerig/runtime/audio/mouth_stream.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "support/test_audio.h"

namespace facerig {
namespace {

using test::kSpeechRate;
using test::Silence;

// A vowel-like buzz (120 Hz pulses, -6 dB per octave) through one formant
// resonator, or high-passed noise for a fricative; peak 0.5.
std::vector<float> Sound(double seconds, double formant_hz, bool noise) {
  std::vector<float> out(static_cast<std::size_t>(seconds * kSpeechRate));
  std::uint32_t state = 3;
  float source = 0.0f;
  for (std::size_t i = 0; i < out.size(); ++i) {
    state = state * 1664525u + 1013904223u;
    if (noise) {
      out[i] = float(state >> 8) / float(1u << 24) - 0.5f;
    } else {
      out[i] = source = (i % (kSpeechRate / 120) == 0 ? 1.0f : 0.0f) + 0.97f * source;
    }
  }
  if (noise) {
    for (int pass = 0; pass < 3; ++pass) {
      for (std::size_t i = out.size() - 1; i > 0; --i) out[i] -= out[i - 1];
    }
  } else {
    const double r = std::exp(-std::numbers::pi * 80.0 / kSpeechRate);
    const double a1 = 2.0 * r * std::cos(2.0 * std::numbers::pi * formant_hz / kSpeechRate), a2 = -r * r;
    double y1 = 0.0, y2 = 0.0;
    for (float& x : out) {
      const double y = (1.0 - a1 - a2) * x + a1 * y1 + a2 * y2;
      y2 = y1;
      y1 = y;
      x = static_cast<float>(y);
    }
  }
  float peak = 0.0f;
  for (const float x : out) peak = std::max(peak, std::abs(x));
  for (float& x : out) x *= 0.5f / peak;
  return out;
}


std::vector<float> TestLine() {
  std::vector<float> line;
  for (const auto& part : {Silence(0.3), Sound(0.4, 750.0, false), Silence(0.08), Sound(0.3, 750.0, false),
                           Sound(0.2, 0.0, true), Silence(0.5), Sound(0.3, 750.0, false), Silence(0.2)}) {
    line.insert(line.end(), part.begin(), part.end());
  }
  return line;
}

// Symbols with repeats (the pieces of one long segment) joined.
std::string Collapsed(const std::vector<Phoneme>& phonemes) {
  std::string out;
  std::string previous;
  for (const Phoneme& p : phonemes) {
    const std::string symbol(p.symbol.view());
    if (symbol != previous) out += symbol + " ";
    previous = symbol;
  }
  return out;
}

std::vector<Phoneme> Stream(RoughMouthStream& stream, const std::vector<float>& audio, std::size_t chunk) {
  std::vector<Phoneme> out;
  for (std::size_t at = 0; at < audio.size(); at += chunk) {
    const std::size_t n = std::min(chunk, audio.size() - at);
    stream.Push(std::span<const float>(audio).subspan(at, n), out);
    // Bounded look-ahead: the phonemes so far reach back to within latency() of the audio.
    const double pushed = double(at + n) / kSpeechRate;
    const double covered = out.empty() ? 0.0 : out.back().start.count() + out.back().duration.count();
    CHECK(covered >= pushed - stream.latency() - 1e-9);
    CHECK(covered <= pushed + 1e-9);
  }
  stream.Finish(out);
  return out;
}

TEST_CASE("audio mouth stream: same segments as the whole buffer, bounded look-ahead", "[audio_mouth]") {
  const std::vector<float> audio = TestLine();
  const std::optional<SpeechLine> whole = RoughMouthFromAudio(audio, kSpeechRate);
  REQUIRE(whole);
  REQUIRE(Collapsed(whole->phonemes) == "_ a b a s _ a _ ");
  RoughMouthStream stream(kSpeechRate);
  REQUIRE(stream.valid());
  CHECK(stream.latency() <= 0.3);
  for (const std::size_t chunk : {std::size_t{1}, std::size_t{37}, std::size_t{160}, std::size_t{4096}, audio.size()}) {
    INFO("chunk " << chunk);
    const std::vector<Phoneme> streamed = Stream(stream, audio, chunk);  // Finish() resets for the next line
    CHECK(Collapsed(streamed) == Collapsed(whole->phonemes));
    REQUIRE_FALSE(streamed.empty());
    CHECK(streamed.front().start.count() == 0.0);
    for (std::size_t i = 0; i + 1 < streamed.size(); ++i) {
      CHECK(streamed[i].duration.count() > 0.0);
      CHECK(streamed[i].duration.count() <= 0.1 + 1e-9);
      CHECK(streamed[i].start.count() + streamed[i].duration.count() ==
            Approx(streamed[i + 1].start.count()));
    }
    CHECK(streamed.back().start.count() + streamed.back().duration.count() == Approx(double(audio.size()) / kSpeechRate));
  }
}

TEST_CASE("audio mouth stream: int16 input and invalid streams", "[audio_mouth]") {
  const std::vector<float> audio = TestLine();
  std::vector<std::int16_t> pcm(audio.size());
  for (std::size_t i = 0; i < audio.size(); ++i) pcm[i] = static_cast<std::int16_t>(std::lround(audio[i] * 32767.0f));
  RoughMouthStream stream(kSpeechRate);
  std::vector<Phoneme> out;
  stream.Push(pcm, out);
  stream.Finish(out);
  CHECK(Collapsed(out) == "_ a b a s _ a _ ");

  for (const int rate : {0, -8000, kMouthMaxSampleRate + 1}) {
    RoughMouthStream bad(rate);
    CHECK_FALSE(bad.valid());
    CHECK(bad.latency() == 0.0);
    std::vector<Phoneme> none;
    bad.Push(audio, none);
    bad.Finish(none);
    CHECK(none.empty());
  }
  // Nothing pushed: nothing out.
  std::vector<Phoneme> none;
  stream.Finish(none);
  CHECK(none.empty());
}

}  // namespace
}  // namespace facerig
