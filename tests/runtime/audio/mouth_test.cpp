#include "facerig/runtime/audio/mouth.h"

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <numbers>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/runtime/io/phoneme_track_file.h"
#include "facerig/runtime/speech/phoneme_visemes.h"
#include "support/test_audio.h"

namespace facerig {
namespace {

constexpr int kVoiceRate = 22050;  // espeak-ng's

std::vector<float> Quiet(double seconds) { return test::Silence(seconds, kVoiceRate); }

struct Formant {
  double hz;
  double bandwidth;
};

// A vowel-like buzz: a 120 Hz pulse train sloping -6 dB per octave (glottal
// source and lip radiation: a one-pole low-pass) through a cascade of two-pole formant
// resonators, peak 0.5.
std::vector<float> Buzz(double seconds, std::initializer_list<Formant> formants) {
  std::vector<float> out(static_cast<std::size_t>(seconds * kVoiceRate));
  const auto period = static_cast<std::size_t>(kVoiceRate / 120.0);
  for (std::size_t i = 0; i < out.size(); i += period) out[i] = 1.0f;
  float source = 0.0f;
  for (float& x : out) x = source = x + 0.97f * source;
  for (const Formant& f : formants) {
    const double r = std::exp(-std::numbers::pi * f.bandwidth / kVoiceRate);
    const double a1 = 2.0 * r * std::cos(2.0 * std::numbers::pi * f.hz / kVoiceRate);
    const double a2 = -r * r;
    double y1 = 0.0, y2 = 0.0;
    for (float& x : out) {
      const double y = (1.0 - a1 - a2) * x + a1 * y1 + a2 * y2;  // unity gain at 0 Hz (Klatt)
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

// White noise, high-passed by three first differences (+18 dB/octave), peak 0.3.
std::vector<float> Hiss(double seconds) {
  std::vector<float> out(static_cast<std::size_t>(seconds * kVoiceRate) + 3);
  std::uint32_t state = 7;
  for (float& x : out) {
    state = state * 1664525u + 1013904223u;
    x = float(state >> 8) / float(1u << 24) - 0.5f;
  }
  for (int pass = 0; pass < 3; ++pass) {
    for (std::size_t i = out.size() - 1; i > 0; --i) out[i] -= out[i - 1];
  }
  out.erase(out.begin(), out.begin() + 3);
  float peak = 0.0f;
  for (const float x : out) peak = std::max(peak, std::abs(x));
  for (float& x : out) x *= 0.3f / peak;
  return out;
}


std::vector<float> Join(std::initializer_list<std::vector<float>> parts) {
  std::vector<float> out;
  for (const auto& part : parts) out.insert(out.end(), part.begin(), part.end());
  return out;
}

const std::initializer_list<Formant> kOpenVowel = {{700, 80}, {1200, 90}, {2600, 150}};
const std::initializer_list<Formant> kFrontVowel = {{280, 60}, {2300, 100}, {3000, 150}};
const std::initializer_list<Formant> kRoundedVowel = {{320, 60}, {800, 80}};

std::string Symbols(const SpeechLine& line) {
  std::string out;
  for (const Phoneme& p : line.phonemes) out += std::string(p.symbol.view()) + " ";
  return out;
}

// Phonemes cover [0, duration] without gaps or overlaps.
void CheckContiguous(const SpeechLine& line, double duration) {
  REQUIRE_FALSE(line.phonemes.empty());
  CHECK(line.phonemes.front().start.count() == 0.0);
  for (std::size_t i = 0; i + 1 < line.phonemes.size(); ++i) {
    const Phoneme& p = line.phonemes[i];
    CHECK(p.duration.count() > 0.0);
    CHECK(p.start.count() + p.duration.count() == Approx(line.phonemes[i + 1].start.count()));
  }
  const Phoneme& last = line.phonemes.back();
  CHECK(last.start.count() + last.duration.count() == Approx(duration));
}

SpeechLine Rough(const std::vector<float>& audio) {
  const std::optional<SpeechLine> line = RoughMouthFromAudio(audio, kVoiceRate);
  REQUIRE(line);
  CheckContiguous(*line, double(audio.size()) / kVoiceRate);
  return *line;
}

TEST_CASE("audio mouth: silence rests, one sound class each", "[audio_mouth]") {
  CHECK(Symbols(Rough(Quiet(1.0))) == "_ ");
  CHECK(Symbols(Rough(Join({Quiet(0.3), Buzz(0.4, kOpenVowel), Quiet(0.3)}))) == "_ a _ ");
  CHECK(Symbols(Rough(Join({Quiet(0.3), Buzz(0.4, kFrontVowel), Quiet(0.3)}))) == "_ i _ ");
  CHECK(Symbols(Rough(Join({Quiet(0.3), Buzz(0.4, kRoundedVowel), Quiet(0.3)}))) == "_ o _ ");
  CHECK(Symbols(Rough(Join({Quiet(0.3), Hiss(0.3), Quiet(0.3)}))) == "_ s _ ");
}

TEST_CASE("audio mouth: timing of a sound between silences", "[audio_mouth]") {
  const SpeechLine line = Rough(Join({Quiet(0.3), Buzz(0.4, kOpenVowel), Quiet(0.3)}));
  REQUIRE(line.phonemes.size() == 3);
  // Within two hops (smoothing and the analysis window blur the edges).
  CHECK(line.phonemes[1].start.count() == Approx(0.3).margin(0.02));
  CHECK(line.phonemes[2].start.count() == Approx(0.7).margin(0.02));
  for (const Phoneme& p : line.phonemes) {
    CHECK(p.language.empty());
    CHECK_FALSE(p.word_start);
  }
}

TEST_CASE("audio mouth: short gaps close the lips, long ones rest, blips vanish", "[audio_mouth]") {
  const auto open = [] { return Buzz(0.3, kOpenVowel); };
  CHECK(Symbols(Rough(Join({Quiet(0.2), open(), Quiet(0.08), open(), Quiet(0.2)}))) ==
        "_ a b a _ ");
  CHECK(Symbols(Rough(Join({Quiet(0.2), open(), Quiet(0.4), open(), Quiet(0.2)}))) ==
        "_ a _ a _ ");
  // Shorter than the 50 ms minimum segment: merged into the sound around it.
  CHECK(Symbols(Rough(Join({Quiet(0.2), open(), Quiet(0.015), open(), Quiet(0.2)}))) ==
        "_ a _ ");
  // A click of sound inside silence is merged into the silence.
  std::vector<float> click = Quiet(1.0);
  const std::vector<float> blip = Buzz(0.02, kOpenVowel);
  std::copy(blip.begin(), blip.end(), click.begin() + kVoiceRate / 2);
  CHECK(Symbols(Rough(click)) == "_ ");
  // Speech from the first sample: no leading rest.
  CHECK(Symbols(Rough(Join({Buzz(0.3, kFrontVowel), Hiss(0.2), Buzz(0.3, kOpenVowel), Quiet(0.3)}))) ==
        "i s a _ ");
}

TEST_CASE("audio mouth: steady noise alone keeps the mouth at rest", "[audio_mouth]") {
  std::vector<float> noise(kVoiceRate);
  std::uint32_t state = 5;
  for (float& x : noise) {
    state = state * 1664525u + 1013904223u;
    x = 0.03f * (float(state >> 8) / float(1u << 24) - 0.5f);  // about -40 dBFS
  }
  CHECK(Symbols(Rough(noise)) == "_ ");
}

TEST_CASE("audio mouth: the classes survive a quiet recording with a noise floor", "[audio_mouth]") {
  std::vector<float> audio =
      Join({Quiet(0.3), Buzz(0.3, kOpenVowel), Quiet(0.08), Buzz(0.3, kFrontVowel), Quiet(0.3)});
  std::uint32_t state = 99;
  for (float& x : audio) {
    state = state * 1664525u + 1013904223u;
    x = 0.1f * x + 0.0005f * (float(state >> 8) / float(1u << 24) - 0.5f);
  }
  CHECK(Symbols(Rough(audio)) == "_ a b i _ ");
  // int16 input gives the same track.
  std::vector<std::int16_t> pcm(audio.size());
  for (std::size_t i = 0; i < audio.size(); ++i) pcm[i] = static_cast<std::int16_t>(std::lround(audio[i] * 32767.0f));
  const std::optional<SpeechLine> from_pcm = RoughMouthFromAudio(pcm, kVoiceRate);
  REQUIRE(from_pcm);
  CHECK(Symbols(*from_pcm) == "_ a b i _ ");
}

TEST_CASE("audio mouth: every symbol maps to its viseme in every language", "[audio_mouth]") {
  const std::pair<MouthShape, Viseme> expected[] = {
      {MouthShape::kRest, Viseme::kSil},   {MouthShape::kClosed, Viseme::kPP},
      {MouthShape::kOpen, Viseme::kAA},    {MouthShape::kFront, Viseme::kIH},
      {MouthShape::kRounded, Viseme::kOH}, {MouthShape::kFricative, Viseme::kSS}};
  for (const char* language : {"", "en-us", "en", "pt-br", "pt", "es", "fr", "de", "it", "fi", "nl",
                               "pl", "ru", "hi", "cmn", "xx"}) {
    for (const auto& [shape, viseme] : expected) {
      INFO(language << " " << RoughMouthSymbol(shape));
      const std::optional<PhonemeVisemes> map = LookupPhonemeVisemes(language, RoughMouthSymbol(shape));
      REQUIRE(map);
      CHECK(map->count == 1);
      CHECK(map->visemes[0] == viseme);
      CHECK(map->strength == 1.0f);
      // No timing shifts: the track's times are the sound's.
      CHECK_FALSE(map->has(PhonemeVisemes::kUnvoicedStop));
      CHECK_FALSE(map->has(PhonemeVisemes::kLagSource));
    }
  }
}

TEST_CASE("audio mouth: the track round-trips through a phoneme-track file", "[audio_mouth]") {
  AudioMouthParams params;
  params.language = LanguageName("en-us");
  const std::optional<SpeechLine> line =
      RoughMouthFromAudio(Join({Quiet(0.2), Buzz(0.3, kOpenVowel), Quiet(0.2)}), kVoiceRate, params);
  REQUIRE(line);
  CHECK(line->language.view() == "en-us");
  const PhonemeTrack track = ParsePhonemeTrack(FormatPhonemeTrack(*line));
  REQUIRE(track.line.phonemes.size() == line->phonemes.size());
  for (std::size_t i = 0; i < line->phonemes.size(); ++i) {
    CHECK(track.line.phonemes[i].symbol == line->phonemes[i].symbol);
    CHECK(track.line.phonemes[i].language.view() == "en-us");
    CHECK(track.line.phonemes[i].start.count() == Approx(line->phonemes[i].start.count()));
  }
}

TEST_CASE("audio mouth: invalid inputs", "[audio_mouth]") {
  const std::vector<float> audio = Buzz(0.2, kOpenVowel);
  CHECK_FALSE(RoughMouthFromAudio(audio, 0));
  CHECK_FALSE(RoughMouthFromAudio(audio, -22050));
  CHECK_FALSE(RoughMouthFromAudio(audio, kMouthMaxSampleRate + 1));
  AudioMouthParams params;
  params.analysis.hop = -0.01;
  CHECK_FALSE(RoughMouthFromAudio(audio, kVoiceRate, params));
  const std::optional<SpeechLine> empty = RoughMouthFromAudio(std::span<const float>(), kVoiceRate);
  REQUIRE(empty);
  CHECK(empty->phonemes.empty());
  CHECK(ClassifyMouthFrames({}).empty());
  const std::vector<MouthShape> shapes(10, MouthShape::kOpen);
  CHECK(MouthShapesToPhonemes(shapes, 0.0, 0.1).empty());
  CHECK(MouthShapesToPhonemes(shapes, std::nan(""), 0.1).empty());
  // A bad duration is taken as 0; phonemes stay finite and ordered.
  const std::vector<Phoneme> clamped = MouthShapesToPhonemes(shapes, 0.01, -1.0);
  REQUIRE(clamped.size() == 1);
  CHECK(clamped[0].duration.count() == 0.0);
}

TEST_CASE("audio mouth: segments from hand-made frame shapes", "[audio_mouth]") {
  using S = MouthShape;
  // 10 ms frames: rest 20, fricative 3 (too short: taken by the longer rest), open 10,
  // rest 8 (80 ms inside speech: closed), front 10, rest 20.
  const std::pair<S, int> runs[] = {{S::kRest, 20}, {S::kFricative, 3}, {S::kOpen, 10},
                                    {S::kRest, 8},  {S::kFront, 10},    {S::kRest, 20}};
  std::vector<S> shapes;
  for (const auto& [shape, count] : runs) {
    for (int i = 0; i < count; ++i) shapes.push_back(shape);
  }
  const std::vector<Phoneme> phonemes = MouthShapesToPhonemes(shapes, 0.01, 0.71);
  std::string symbols;
  for (const Phoneme& p : phonemes) symbols += std::string(p.symbol.view()) + " ";
  CHECK(symbols == "_ a b i _ ");
  REQUIRE(phonemes.size() == 5);
  // Run boundaries sit half a hop before the run's first frame centre.
  CHECK(phonemes[1].start.count() == Approx(0.225));
  CHECK(phonemes[2].start.count() == Approx(0.325));
  CHECK(phonemes[4].start.count() + phonemes[4].duration.count() == Approx(0.71));
}

}  // namespace
}  // namespace facerig
