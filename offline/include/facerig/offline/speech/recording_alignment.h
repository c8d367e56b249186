// A recording and its transcript to a phoneme track: the transcript is
// synthesized by a PhonemeSource (e.g. espeak-ng, which gives exact phoneme
// boundaries on its own audio), the recording is brought to the synthetic
// audio's rate, and the two are aligned (phoneme_alignment.h).
#pragma once

#include <string_view>

#include "facerig/runtime/io/audio_file.h"
#include "facerig/runtime/alignment/phoneme_alignment.h"
#include "facerig/runtime/speech/phoneme_source.h"

namespace facerig {

// Below this PhonemeAlignment::confidence a recording and its transcript are
// taken not to match (`facerig align` refuses to write the track). From
// `facerig-bench align --sections confidence` on pocketsphinx-testdata's 10
// real recordings: with their own transcript 0.074-0.173 (the lowest are the
// 1-2 s `cards` lines), with another line's -0.033-0.100 (median 0.049),
// white noise 0.013-0.046. Below every matched pair with a margin, above all
// noise; with the tempo rule below it refuses 67 of the 90 mismatched pairs,
// none of the matched ones.
inline constexpr double kDefaultMinMatchConfidence = 0.06;
// Nor do they when the recording's speech lasts more than this many times the
// transcript's rendition (espeak-ng at 175 wpm), or less than its inverse:
// readers with their own pauses lie within 0.78-1.18 on those recordings;
// this refuses 8 more of the 90 mismatched pairs there.
inline constexpr double kMaxTempoRatio = 2.0;

// The recording and the transcript seem to match (see above).
inline bool TranscriptFits(const PhonemeAlignment& alignment, double min_confidence) {
  return alignment.confidence >= min_confidence && alignment.tempo <= kMaxTempoRatio &&
         alignment.tempo >= 1.0 / kMaxTempoRatio;
}

struct RecordingAlignment {
  PhonemeAlignment alignment;  // phonemes timed on the recording
  SpeechLine reference;        // the synthetic rendition it was aligned with
  double seconds = 0.0;        // wall time: synthesis, resampling and alignment
};

// \throw SpeechError from the source (unknown voice, bad text), AlignmentError
// when the text gives no speech or the alignment cannot run (see
// AlignPhonemesToRecording).
RecordingAlignment AlignRecording(PhonemeSource& source, const AudioClip& recording, std::string_view transcript,
                                  std::string_view voice, const PhonemeAlignmentParams& params = {});

}  // namespace facerig
