// Whether a recording and its transcript seem to match, from what the
// alignment measured (PhonemeAlignment::confidence and tempo). Shared by
// `facerig align` and the C ABI's fr_speech_align, so every host refuses the
// same pairs.
#pragma once

#include "facerig/runtime/alignment/phoneme_alignment.h"

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
inline bool TranscriptFits(const PhonemeAlignment& alignment, double min_confidence = kDefaultMinMatchConfidence) {
  return alignment.confidence >= min_confidence && alignment.tempo <= kMaxTempoRatio &&
         alignment.tempo >= 1.0 / kMaxTempoRatio;
}

}  // namespace facerig
