// Pauses in recordings: found by loudness and length, crossed by the warping
// without stretching a phoneme into them, offline and streaming. Tones of
// different pitch stand in for phonemes (no speech engine).
#include "facerig/runtime/alignment/pauses.h"

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/runtime/alignment/phoneme_alignment.h"
#include "facerig/runtime/alignment/streaming_alignment.h"
#include "facerig/runtime/io/audio_file.h"
#include "support/test_audio.h"

namespace facerig {
namespace {

using test::kSpeechRate;
constexpr double kHop = 0.01;

// Log energies: `quiet` frames at -10, loud ones at 0, in runs of the given lengths.
std::vector<float> Energies(const std::vector<std::pair<bool, std::size_t>>& runs) {
  std::vector<float> energy;
  for (const auto& [quiet, frames] : runs) energy.insert(energy.end(), frames, quiet ? -10.0f : 0.0f);
  return energy;
}

TEST_CASE("FindPauses: 0.15 s of quiet at the ends, 0.25 s inside", "[pauses]") {
  // 0.15 s quiet first, speech, 0.20 s quiet (a long closure, no pause), speech,
  // 0.25 s quiet (a pause), speech, 0.14 s quiet at the end (too short).
  const std::vector<float> energy =
      Energies({{true, 15}, {false, 50}, {true, 20}, {false, 50}, {true, 25}, {false, 50}, {true, 14}});
  const std::vector<Pause> pauses = FindPauses(energy, kHop);
  REQUIRE(pauses.size() == 2);
  CHECK(pauses[0].first == 0);
  CHECK(pauses[0].last == 14);
  CHECK(pauses[1].first == 135);
  CHECK(pauses[1].last == 159);
  // Quiet only relative to the range: the same frames 1.5 apart are no pauses.
  std::vector<float> flat = energy;
  for (float& e : flat) e = e < -1.0f ? -1.5f : 0.0f;
  CHECK(FindPauses(flat, kHop).empty());
  // The frames a quarter of the way up from the quiet end still count as quiet.
  std::vector<float> ramp = energy;
  for (std::size_t f = 0; f < 15; ++f) ramp[f] = -7.6f;
  CHECK(FindPauses(ramp, kHop).size() == 2);
  for (std::size_t f = 0; f < 15; ++f) ramp[f] = -7.4f;
  CHECK(FindPauses(ramp, kHop).size() == 1);
  const std::vector<bool> mask = PauseMask(pauses, energy.size());
  CHECK(mask[0]);
  CHECK_FALSE(mask[15]);
  CHECK(mask[140]);
  CHECK_FALSE(mask.back());
}

TEST_CASE("FindPauses: the edges are silence up to the speech's rise, over room tone louder than the quietest frames", "[pauses]") {
  // 0.2 s of silence an editor added (-12), 0.2 s of the recording's room tone
  // (-9: above the quiet share of the way from -12 to the speech's 0), the
  // rise, 1 s of speech, the fall, room tone and added silence again.
  std::vector<float> energy(20, -12.0f);
  energy.insert(energy.end(), 20, -9.0f);
  for (const float e : {-6.0f, -3.0f}) energy.push_back(e);
  energy.insert(energy.end(), 100, 0.0f);
  for (const float e : {-3.0f, -6.0f}) energy.push_back(e);
  energy.insert(energy.end(), 20, -9.0f);
  energy.insert(energy.end(), 20, -12.0f);
  const std::vector<Pause> pauses = FindPauses(energy, kHop);
  REQUIRE(pauses.size() == 2);
  CHECK(pauses[0].first == 0);
  CHECK(pauses[0].last >= 36);  // the room tone too, up to where the rise begins
  CHECK(pauses[0].last < 40);
  CHECK(pauses[1].first > 142);
  CHECK(pauses[1].first <= 147);
  CHECK(pauses[1].last == energy.size() - 1);
}

struct Tones {
  std::vector<float> audio;
  std::vector<double> starts;  // each tone's start
};

// Tones of `hz` lasting `seconds`, with `gap_before[i]` seconds of silence
// before tone i and `trail` after the last; faint deterministic noise throughout.
Tones Render(const std::vector<double>& hz, const std::vector<double>& seconds, const std::vector<double>& gap_before,
             double trail, float amplitude) {
  Tones tones;
  for (std::size_t i = 0; i < hz.size(); ++i) {
    tones.audio.resize(tones.audio.size() + static_cast<std::size_t>(gap_before[i] * kSpeechRate), 0.0f);
    tones.starts.push_back(static_cast<double>(tones.audio.size()) / kSpeechRate);
    const std::vector<float> tone = test::Sine(hz[i], seconds[i], kSpeechRate, amplitude);
    tones.audio.insert(tones.audio.end(), tone.begin(), tone.end());
  }
  tones.audio.resize(tones.audio.size() + static_cast<std::size_t>(trail * kSpeechRate), 0.0f);
  std::uint32_t state = 99;
  for (float& v : tones.audio) {
    state = state * 1664525u + 1013904223u;
    v += 0.001f * (static_cast<float>(state >> 8) / 8388608.0f - 1.0f);
  }
  return tones;
}

const std::vector<double> kHz = {250, 900, 2400, 500, 1500, 700};
const std::vector<double> kReferenceSeconds = {0.20, 0.15, 0.20, 0.25, 0.15, 0.20};
const std::vector<double> kRecordingSeconds = {0.25, 0.20, 0.15, 0.30, 0.20, 0.25};

constexpr double kReferenceEdge = 0.05;  // silence before and after the reference's tones, as a synthesizer leaves

Phoneme Timed(double start, double duration, const char* symbol) {
  Phoneme p;
  p.start = Seconds(start);
  p.duration = Seconds(duration);
  p.symbol.assign(symbol);
  return p;
}

// The reference: a pause phoneme, the tones back to back (a phoneme each),
// a pause phoneme; no pause between the tones.
SpeechLine Reference() {
  std::vector<double> gaps(kHz.size(), 0.0);
  gaps[0] = kReferenceEdge;
  const Tones tones = Render(kHz, kReferenceSeconds, gaps, kReferenceEdge, 0.5f);
  SpeechLine reference;
  reference.sample_rate = kSpeechRate;
  reference.audio = FloatToPcm(tones.audio);
  reference.phonemes.push_back(Timed(0.0, kReferenceEdge, "_"));
  for (std::size_t i = 0; i < kHz.size(); ++i) {
    reference.phonemes.push_back(Timed(tones.starts[i], kReferenceSeconds[i], i % 2 == 0 ? "a" : "o"));
  }
  reference.phonemes.push_back(Timed(tones.starts.back() + kReferenceSeconds.back(), kReferenceEdge, "_"));
  return reference;
}

// The recording: 1 s of silence first, 0.6 s before the fourth tone, 0.5 s after.
Tones Recording() { return Render(kHz, kRecordingSeconds, {1.0, 0.0, 0.0, 0.6, 0.0, 0.0}, 0.5, 0.2f); }

TEST_CASE("AlignPhonemesToRecording: no phoneme is stretched into silence before or inside the speech", "[pauses][phoneme_alignment]") {
  const SpeechLine reference = Reference();
  const Tones recording = Recording();
  const PhonemeAlignment aligned = AlignPhonemesToRecording(reference, recording.audio);
  REQUIRE(aligned.line.phonemes.size() == kHz.size() + 2);
  CHECK(aligned.pauses == 3);
  for (std::size_t i = 0; i < kHz.size(); ++i) {
    INFO("tone " << i);
    CHECK(aligned.line.phonemes[i + 1].start.count() == Approx(recording.starts[i]).margin(0.020));
  }
  // The tone before the inner pause ends where the pause begins.
  const Phoneme& before = aligned.line.phonemes[3];
  CHECK((before.start + before.duration).count() == Approx(recording.starts[2] + kRecordingSeconds[2]).margin(0.020));
  // Without pauses (the earlier behaviour) the first tone starts at the recording's start.
  PhonemeAlignmentParams old;
  old.pauses = false;
  const PhonemeAlignment stretched = AlignPhonemesToRecording(reference, recording.audio, old);
  CHECK(stretched.pauses == 0);
  CHECK(stretched.line.phonemes[1].start.count() < 0.5);
}

TEST_CASE("StreamingAligner: the warping waits while the recording is quiet", "[pauses][stream]") {
  const SpeechLine reference = Reference();
  const Tones recording = Recording();
  StreamingAligner aligner(reference);  // pauses on by default
  std::vector<double> starts(kHz.size() + 2, -1.0);
  const auto take = [&](std::span<const StreamedBoundary> boundaries) {
    for (const StreamedBoundary& b : boundaries) starts[b.phoneme] = b.start.count();
  };
  constexpr std::size_t kChunk = 320;
  for (std::size_t at = 0; at < recording.audio.size(); at += kChunk) {
    take(aligner.Push(std::span<const float>(recording.audio).subspan(at, std::min(kChunk, recording.audio.size() - at))));
  }
  take(aligner.Finish());
  for (std::size_t i = 0; i < kHz.size(); ++i) {
    INFO("tone " << i);
    CHECK(starts[i + 1] == Approx(recording.starts[i]).margin(0.030));
  }
}

}  // namespace
}  // namespace facerig
