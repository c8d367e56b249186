// The alignment core on signals with known boundaries (no speech engine):
// tones of different pitch as "phonemes", the recording slower in places,
// faster in others, quieter, noisy and with leading silence.
#include "facerig/runtime/alignment/phoneme_alignment.h"

#include <cmath>
#include <cstdint>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/runtime/io/audio_file.h"
#include "support/test_audio.h"

namespace facerig {
namespace {

using test::kSpeechRate;

struct Segment {
  double hz;  // 0: silence
  double seconds;
};

std::vector<float> Render(const std::vector<Segment>& segments, float amplitude, double* starts) {
  std::vector<float> audio;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    starts[s] = static_cast<double>(audio.size()) / kSpeechRate;
    const std::vector<float> tone = segments[s].hz > 0.0 ? test::Sine(segments[s].hz, segments[s].seconds, kSpeechRate, amplitude)
                                                         : std::vector<float>(static_cast<std::size_t>(segments[s].seconds * kSpeechRate), 0.0f);
    audio.insert(audio.end(), tone.begin(), tone.end());
  }
  return audio;
}

TEST_CASE("AlignPhonemesToRecording: tone boundaries land within 20 ms", "[phoneme_alignment]") {
  const double hz[] = {0, 250, 900, 0, 2400, 500, 1500, 0};
  const double reference_seconds[] = {0.05, 0.20, 0.15, 0.10, 0.20, 0.25, 0.15, 0.05};
  const double recording_seconds[] = {0.40, 0.30, 0.10, 0.25, 0.15, 0.30, 0.20, 0.30};
  std::vector<Segment> reference_segments, recording_segments;
  for (int s = 0; s < 8; ++s) {
    reference_segments.push_back({hz[s], reference_seconds[s]});
    recording_segments.push_back({hz[s], recording_seconds[s]});
  }
  double reference_starts[8], recording_starts[8];
  SpeechLine reference;
  reference.sample_rate = kSpeechRate;
  reference.audio = FloatToPcm(Render(reference_segments, 0.5f, reference_starts));
  for (int s = 0; s < 8; ++s) {
    Phoneme p;
    p.start = Seconds(reference_starts[s]);
    p.duration = Seconds(reference_seconds[s]);
    p.symbol.assign(hz[s] > 0 ? "a" : "_");
    reference.phonemes.push_back(p);
  }
  std::vector<float> recording = Render(recording_segments, 0.1f, recording_starts);
  std::uint32_t state = 12345;  // deterministic noise, 40 dB below the tones
  for (float& v : recording) {
    state = state * 1664525u + 1013904223u;
    v += 0.001f * (static_cast<float>(state >> 8) / 8388608.0f - 1.0f);
  }

  const PhonemeAlignment result = AlignPhonemesToRecording(reference, recording);
  REQUIRE(result.line.phonemes.size() == 8);
  for (int s = 1; s < 8; ++s) {
    INFO("segment " << s);
    CHECK(result.line.phonemes[static_cast<std::size_t>(s)].start.count() == Approx(recording_starts[s]).margin(0.020));
  }
  double previous = 0.0;
  for (const Phoneme& p : result.line.phonemes) {
    CHECK(p.start.count() >= previous);
    CHECK(p.duration.count() >= 0.0);
    previous = p.start.count();
  }
  CHECK(previous <= static_cast<double>(recording.size()) / kSpeechRate);
}

TEST_CASE("AlignPhonemesToRecording: invalid inputs are AlignmentErrors", "[phoneme_alignment]") {
  SpeechLine reference;
  reference.sample_rate = kSpeechRate;
  const std::vector<float> recording = test::Sine(440.0, 0.5, kSpeechRate);
  CHECK_THROWS_AS(AlignPhonemesToRecording(reference, recording), AlignmentError);  // no audio
  reference.audio = FloatToPcm(recording);
  CHECK_THROWS_AS(AlignPhonemesToRecording(reference, recording), AlignmentError);  // no phonemes
  reference.phonemes.push_back(Phoneme{});
  CHECK_THROWS_AS(AlignPhonemesToRecording(reference, {}), AlignmentError);  // no recording
  PhonemeAlignmentParams tiny;
  tiny.max_cells = 100;
  CHECK_THROWS_AS(AlignPhonemesToRecording(reference, recording, tiny), AlignmentError);
  CHECK(AlignPhonemesToRecording(reference, recording).line.phonemes.size() == 1);
}

}  // namespace
}  // namespace facerig
