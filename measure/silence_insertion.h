// Silence put into a synthetic recording, with its truth moved along: before
// the speech, at its middle word and after it, over faint room noise. Shared
// by the alignment tests and `facerig-bench align --sections silence`.
#pragma once

#include <cstddef>
#include <random>

#include "facerig/runtime/io/audio_file.h"
#include "facerig/runtime/speech/phoneme.h"

namespace facerig::test {

// Room noise under the silence and the speech: RMS 1e-3, -60 dBFS.
inline constexpr float kRoomNoiseRms = 1e-3f;

struct SilenceLayout {
  double before = 0.0, inside = 0.0, after = 0.0;  // seconds
};

struct SilencedRecording {
  SpeechLine truth;    // the phonemes shifted with the inserted silence; no audio
  AudioClip clip;
  std::size_t inner = 0;  // the first phoneme after the inner silence (0: none)
};

// The word start nearest the middle of the line (not the first word); 0 when
// the line has a single word.
std::size_t MiddleWord(const SpeechLine& line);

// `spoken` (audio and exact phonemes) with `layout`'s silence inserted and
// room noise from `random` added throughout.
SilencedRecording WithSilence(const SpeechLine& spoken, const SilenceLayout& layout, std::mt19937& random);

}  // namespace facerig::test
