// A whole recording aligned to a reference line (fr_speech_align).
#include <cmath>
#include <span>

#include "boundary.h"
#include "facerig/runtime/alignment/transcript_fit.h"
#include "facerig/runtime/io/audio_file.h"
#include "handles.h"

extern "C" {

fr_status fr_speech_align(const fr_speech* reference, const float* samples, size_t sample_count,
                          int32_t sample_rate, fr_alignment_fit* fit, fr_speech** out_speech) {
  using facerig::capi::Fail;
  return facerig::capi::Guard([&] {
    FR_REQUIRE(out_speech, "out_speech");
    *out_speech = nullptr;
    FR_REQUIRE(reference, "reference");
    FR_REQUIRE(samples, "samples");
    if (sample_count == 0) return Fail(FR_ERROR_INVALID_ARGUMENT, "the recording has no samples");
    if (reference->samples.empty()) return Fail(FR_ERROR_SPEECH, "the reference line has no audio to align with");
    if (sample_rate != reference->sample_rate) {
      return Fail(FR_ERROR_INVALID_ARGUMENT, {"the recording is at ", std::to_string(sample_rate),
                                              " Hz, the reference at ", std::to_string(reference->sample_rate),
                                              " Hz: resample it first"});
    }
    const std::span<const float> recording(samples, sample_count);
    for (std::size_t i = 0; i < sample_count; ++i) {
      if (!std::isfinite(samples[i])) return Fail(FR_ERROR_INVALID_ARGUMENT, "the recording has a NaN or infinite sample");
    }
    facerig::SpeechLine line = reference->line;
    line.sample_rate = reference->sample_rate;
    line.audio = facerig::FloatToPcm(reference->samples);
    facerig::PhonemeAlignment alignment = facerig::AlignPhonemesToRecording(line, recording);
    if (fit != nullptr) {
      *fit = {alignment.confidence, alignment.tempo, facerig::TranscriptFits(alignment) ? 1 : 0, 0};
    }
    fr_speech aligned;
    aligned.line = std::move(alignment.line);
    aligned.samples.assign(recording.begin(), recording.end());
    aligned.sample_rate = sample_rate;
    *out_speech = new fr_speech(std::move(aligned));
    return FR_OK;
  });
}

}  // extern "C"
