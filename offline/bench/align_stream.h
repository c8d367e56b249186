// facerig-bench align: the streaming aligner run as a client would, its result
// in AlignRecording's form.
#pragma once

#include <string>

#include "facerig/offline/speech/recording_alignment.h"
#include "facerig/runtime/alignment/streaming_alignment.h"

// The clip (resampled to the reference's rate when needed) pushed in chunks
// of `chunk_ms`; each phoneme's duration runs to the next start. `seconds`
// includes the reference's synthesis.
facerig::RecordingAlignment StreamAlign(facerig::PhonemeSource& aligner, const facerig::AudioClip& clip,
                                        const std::string& sentence, const std::string& voice, double chunk_ms,
                                        const facerig::StreamingAlignmentParams& params = {});
