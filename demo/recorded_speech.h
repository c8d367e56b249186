// A recording to speak: --audio FILE with its transcript (--text, aligned on
// the spot with espeak-ng as the reference) or with a phoneme track (--track,
// e.g. from `facerig align`; its "audio" names the recording when --audio is
// not given), or alone: the rough mode (RoughMouthFromAudio, a coarse mouth
// from loudness and spectrum).
#pragma once

#include "facerig/runtime/speech/phoneme.h"
#include "player_options.h"

namespace facerig::player {

// True when the options ask for a recording rather than synthesized speech.
bool WantsRecordedSpeech(const PlayerOptions& options);

// True for --audio without --text or --track: the rough mode.
bool WantsRoughMode(const PlayerOptions& options);

// The line to speak: the track's or the alignment's phonemes and the
// recording's audio, resampled to `sample_rate` (0: the file's own rate).
// Throws IoError (unreadable audio or track, naming the file), SpeechError
// (bad voice), AlignmentError, std::runtime_error (a track naming no audio).
SpeechLine LoadRecordedSpeech(const PlayerOptions& options, int sample_rate);

}  // namespace facerig::player
