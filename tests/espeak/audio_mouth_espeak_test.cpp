// The rough (audio-only) mouth against espeak-ng's own phoneme events: the
// events say exactly when the mouth is open, so espeak speech gives a truth.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "corpus.h"
#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/runtime/audio/mouth.h"
#include "facerig/runtime/audio/mouth_stream.h"
#include "facerig/runtime/speech/phoneme_visemes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

constexpr double kHop = 0.010;

using test::Corpus;

// The viseme shown at the centre of each 10 ms frame of a track (sil where no key).
std::vector<Viseme> FrameVisemes(const std::vector<Phoneme>& phonemes, double duration) {
  const std::vector<VisemeKey> keys = PhonemesToVisemeKeys(phonemes);
  const auto count = static_cast<std::size_t>(duration / kHop);
  std::vector<Viseme> frames(count, Viseme::kSil);
  std::size_t k = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const double t = double(i) * kHop;
    while (k < keys.size() && keys[k].end.count() <= t) ++k;
    if (k < keys.size() && keys[k].start.count() <= t) frames[i] = keys[k].viseme;
  }
  return frames;
}

bool IsClosed(Viseme v) { return v == Viseme::kSil || v == Viseme::kPP; }

using test::IsPause;

struct Agreement {
  std::size_t frames = 0;
  std::size_t agree = 0;
  std::size_t pauses = 0;        // espeak pauses longer than kLongPause
  std::size_t pauses_open = 0;   // of which the rough track opens inside
  double fraction() const { return frames ? double(agree) / double(frames) : 0.0; }
};

constexpr double kLongPause = 0.150;
// Pause edges may move by the smoothing (median and minimum segment).
constexpr double kPauseEdge = 0.020;

void Compare(const SpeechLine& line, const std::vector<Phoneme>& rough, Agreement& total) {
  const double duration = line.audio_duration().count();
  const std::vector<Viseme> truth = FrameVisemes(line.phonemes, duration);
  const std::vector<Viseme> guess = FrameVisemes(rough, duration);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    ++total.frames;
    total.agree += IsClosed(truth[i]) == IsClosed(guess[i]);
  }
  for (const Phoneme& p : line.phonemes) {
    if (!IsPause(p) || p.duration.count() <= kLongPause) continue;
    ++total.pauses;
    const auto first = static_cast<std::size_t>((p.start.count() + kPauseEdge) / kHop) + 1;
    const auto end = static_cast<std::size_t>((p.start.count() + p.duration.count() - kPauseEdge) / kHop);
    bool open = false;
    for (std::size_t i = first; i < end && i < guess.size(); ++i) open = open || !IsClosed(guess[i]);
    if (open) {
      ++total.pauses_open;
      UNSCOPED_INFO("open inside the pause at " << p.start.count() << " s of: " << line.text);
    }
  }
}

// The audio as floats, scaled by `gain`, plus white noise of `noise_rms`
// (full scale 1; deterministic): a quieter recording with a noise floor.
std::vector<float> Degraded(const std::vector<std::int16_t>& audio, float gain, float noise_rms) {
  std::vector<float> out(audio.size());
  std::uint32_t state = 12345;
  for (std::size_t i = 0; i < audio.size(); ++i) {
    state = state * 1664525u + 1013904223u;
    const float uniform = float(state >> 8) / float(1u << 24) - 0.5f;  // variance 1/12
    out[i] = gain * float(audio[i]) / 32768.0f + (noise_rms > 0.0f ? noise_rms * 3.4641f * uniform : 0.0f);
  }
  return out;
}

// `lines` lines of `sentences` consecutive corpus sentences each (sentence
// ends are pauses).
// The whole-buffer rough mode, or the stream fed 20 ms chunks.
enum class Mode { kWhole, kStream };

std::vector<Phoneme> RoughPhonemes(std::span<const float> audio, int sample_rate, Mode mode) {
  if (mode == Mode::kWhole) {
    const std::optional<SpeechLine> rough = RoughMouthFromAudio(audio, sample_rate);
    REQUIRE(rough);
    return rough->phonemes;
  }
  RoughMouthStream stream(sample_rate);
  std::vector<Phoneme> out;
  const std::size_t chunk = static_cast<std::size_t>(sample_rate / 50);
  for (std::size_t at = 0; at < audio.size(); at += chunk) {
    stream.Push(audio.subspan(at, std::min(chunk, audio.size() - at)), out);
  }
  stream.Finish(out);
  return out;
}

Agreement Measure(EspeakPhonemeSource& source, const std::string& voice, std::size_t sentences,
                  std::size_t lines, float gain = 1.0f, float noise_rms = 0.0f, Mode mode = Mode::kWhole) {
  Agreement total;
  const std::vector<std::string> corpus = Corpus(voice);
  for (std::size_t i = 0; i + sentences <= corpus.size() && i < lines * sentences; i += sentences) {
    std::string text;
    for (std::size_t j = i; j < i + sentences; ++j) text += corpus[j] + ". ";
    const SpeechLine line = source.Synthesize(text, voice);
    Compare(line, RoughPhonemes(Degraded(line.audio, gain, noise_rms), line.sample_rate, mode), total);
  }
  return total;
}

TEST_CASE("audio mouth: open/closed agrees with espeak-ng's phonemes, long pauses closed",
          "[espeak][audio_mouth]") {
  EspeakPhonemeSource source;
  const Agreement en = Measure(source, "en-us", 3, 12);
  std::printf("audio mouth en-us: %zu frames, open/closed agreement %.3f, %zu long pauses, %zu open\n",
              en.frames, en.fraction(), en.pauses, en.pauses_open);
  CHECK(en.fraction() > 0.85);
  CHECK(en.pauses_open == 0);

  // 12 dB quieter, with white noise at -64 dBFS (some 35 dB below the vowels).
  const Agreement noisy = Measure(source, "en-us", 3, 12, 0.25f, 0.0006f);
  std::printf("audio mouth en-us, -12 dB and noise: agreement %.3f, %zu long pauses, %zu open\n",
              noisy.fraction(), noisy.pauses, noisy.pauses_open);
  CHECK(noisy.fraction() > 0.85);
  CHECK(noisy.pauses_open == 0);

  const Agreement streamed = Measure(source, "en-us", 3, 12, 1.0f, 0.0f, Mode::kStream);
  std::printf("audio mouth en-us, streamed: agreement %.3f, %zu long pauses, %zu open\n",
              streamed.fraction(), streamed.pauses, streamed.pauses_open);
  CHECK(streamed.fraction() > 0.85);
  CHECK(streamed.pauses_open == 0);
}

// Per true viseme: the class features (p10, p50, p90) and the shapes chosen.
using FeatureRows = std::array<std::vector<std::array<float, 4>>, kVisemeCount>;
using Confusion = std::array<std::array<std::size_t, 6>, kVisemeCount>;

void PrintFeatureTable(const FeatureRows& stats, const Confusion& confusion) {
  std::printf("viseme   n   high-low(p10 p50 p90)  front-back(p10 p50 p90)  front-high(p10 p50 p90)"
              "  fric(p10 p50 p90)  | rest closed open front round fric\n");
  for (std::size_t v = 0; v < kVisemeCount; ++v) {
    const auto& rows = stats[v];
    if (rows.empty()) continue;
    std::printf("%-5s %6zu", std::string(ToString(Viseme(v))).c_str(), rows.size());
    for (std::size_t c = 0; c < 4; ++c) {
      std::vector<float> values;
      for (const auto& row : rows) values.push_back(row[c]);
      std::sort(values.begin(), values.end());
      std::printf("  %6.1f %6.1f %6.1f", values[values.size() / 10], values[values.size() / 2],
                  values[values.size() * 9 / 10]);
    }
    std::printf("  |");
    for (std::size_t c = 0; c < 6; ++c) std::printf(" %5zu", confusion[v][c]);
    std::printf("\n");
  }
}

// Vowel frames given a shape of theirs (E is half open and front; oh open and rounded).
void PrintVowelClasses(const Confusion& confusion) {
  using S = MouthShape;
  const std::pair<Viseme, std::vector<S>> vowel_classes[] = {
      {Viseme::kAA, {S::kOpen}},  {Viseme::kE, {S::kOpen, S::kFront}}, {Viseme::kIH, {S::kFront}},
      {Viseme::kOH, {S::kOpen, S::kRounded}}, {Viseme::kOU, {S::kRounded}}};
  std::size_t vowel_frames = 0, vowel_right = 0;
  for (const auto& [viseme, right] : vowel_classes) {
    std::size_t frames = 0, hits = 0;
    for (std::size_t c = 0; c < 6; ++c) {
      frames += confusion[std::size_t(viseme)][c];
      if (std::find(right.begin(), right.end(), S(c)) != right.end()) hits += confusion[std::size_t(viseme)][c];
    }
    std::printf("vowel %-3s: %zu frames, %.2f in its class\n", std::string(ToString(viseme)).c_str(), frames,
                frames ? double(hits) / double(frames) : 0.0);
    vowel_frames += frames;
    vowel_right += hits;
  }
  std::printf("vowels: %.2f of %zu frames in their class\n", double(vowel_right) / double(vowel_frames),
              vowel_frames);
}

// Feature and class statistics per true viseme, for tuning the thresholds,
// and the open/closed agreement per voice.
TEST_CASE("audio mouth: feature statistics per viseme (measurement)", "[espeak][.measure]") {
  EspeakPhonemeSource source;
  const std::vector<std::string> corpus = Corpus("en-us");
  FeatureRows stats;
  Confusion confusion{};
  for (std::size_t i = 0; i < corpus.size(); i += 2) {
    const SpeechLine line = source.Synthesize(corpus[i], "en-us");
    const std::vector<MouthFrameFeatures> frames = AnalyzeMouthFrames(line.audio, line.sample_rate);
    const std::vector<MouthShape> shapes = ClassifyMouthFrames(frames);
    const std::vector<Viseme> truth = FrameVisemes(line.phonemes, line.audio_duration().count());
    for (std::size_t f = 0; f < truth.size() && f < frames.size(); ++f) {
      const MouthFrameFeatures& x = frames[f];
      const float low = x.band(MouthBand::kLowFormant), high = x.band(MouthBand::kHighFormant);
      const float back = x.band(MouthBand::kBackFormant), front = x.band(MouthBand::kFrontFormant);
      const float fric = x.band(MouthBand::kFrication) - std::max({low, high, back, front});
      stats[std::size_t(truth[f])].push_back({high - low, front - back, front - high, fric});
      ++confusion[std::size_t(truth[f])][std::size_t(shapes[f])];
    }
  }
  PrintFeatureTable(stats, confusion);
  PrintVowelClasses(confusion);
  for (const std::string voice : {"en-us", "en", "de", "fr", "es", "ru", "cmn"}) {
    for (const Mode mode : {Mode::kWhole, Mode::kStream}) {
      const Agreement a = Measure(source, voice, 3, 20, 1.0f, 0.0f, mode);
      std::printf("%-6s %-6s %6zu frames, open/closed agreement %.3f, long pauses %zu, open in %zu\n",
                  voice.c_str(), mode == Mode::kWhole ? "whole" : "stream", a.frames, a.fraction(), a.pauses,
                  a.pauses_open);
    }
  }
  // Faster speech has closures shorter than the minimum segment.
  for (const int wpm : {120, 250, 350}) {
    EspeakOptions options;
    options.rate_wpm = wpm;
    EspeakPhonemeSource at_rate(options);
    for (const Mode mode : {Mode::kWhole, Mode::kStream}) {
      const Agreement a = Measure(at_rate, "en-us", 3, 20, 1.0f, 0.0f, mode);
      std::printf("en-us at %d wpm, %-6s: open/closed agreement %.3f, long pauses %zu, open in %zu\n", wpm,
                  mode == Mode::kWhole ? "whole" : "stream", a.fraction(), a.pauses, a.pauses_open);
    }
  }
}

TEST_CASE("audio mouth: analysis time per second of audio (measurement)", "[espeak][.measure]") {
  EspeakPhonemeSource source;
  const std::vector<std::string> corpus = Corpus("en-us");
  std::vector<std::int16_t> audio;
  for (std::size_t i = 0; i < 60; ++i) {
    const SpeechLine line = source.Synthesize(corpus[i], "en-us");
    audio.insert(audio.end(), line.audio.begin(), line.audio.end());
  }
  // About ten minutes: the same speech four times over.
  const std::size_t once = audio.size();
  for (int copy = 0; copy < 3; ++copy) audio.insert(audio.end(), audio.begin(), audio.begin() + std::ptrdiff_t(once));
  const auto start = std::chrono::steady_clock::now();
  const std::optional<SpeechLine> rough = RoughMouthFromAudio(audio, EspeakPhonemeSource::kSampleRate);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  REQUIRE(rough);
  const double audio_seconds = double(audio.size()) / EspeakPhonemeSource::kSampleRate;
  std::printf("audio mouth: %.1f s of audio in %.3f s (%.2f ms per second), %zu phonemes\n", audio_seconds,
              seconds, 1000.0 * seconds / audio_seconds, rough->phonemes.size());
}

}  // namespace
}  // namespace facerig
