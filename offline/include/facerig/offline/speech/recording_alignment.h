// A recording and its transcript to a phoneme track: the transcript is
// synthesized by a PhonemeSource (e.g. espeak-ng, which gives exact phoneme
// boundaries on its own audio), the recording is brought to the synthetic
// audio's rate, and the two are aligned (phoneme_alignment.h).
#pragma once

#include <string_view>

#include "facerig/runtime/io/audio_file.h"
#include "facerig/runtime/alignment/phoneme_alignment.h"
#include "facerig/runtime/alignment/transcript_fit.h"
#include "facerig/runtime/speech/phoneme_source.h"

namespace facerig {

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
