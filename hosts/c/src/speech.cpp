// Speech lines: phoneme tracks, caller phonemes and audio, the rough mode, a
// recording aligned to a reference line.
#include <cmath>
#include <cstring>
#include <string>

#include "boundary.h"
#include "facerig/runtime/alignment/transcript_fit.h"
#include "facerig/runtime/audio/mouth.h"
#include "facerig/runtime/io/audio_file.h"
#include "facerig/runtime/io/phoneme_track_file.h"
#include "handles.h"

namespace facerig::capi {
namespace {

fr_status Publish(fr_speech speech, fr_speech** out_speech) {
  *out_speech = new fr_speech(std::move(speech));
  return FR_OK;
}

fr_status CheckAudio(const float* samples, std::size_t count, std::int32_t sample_rate) {
  if (samples == nullptr && count > 0) return Fail(FR_ERROR_INVALID_ARGUMENT, "samples is NULL");
  if (count > 0 && sample_rate <= 0) return Fail(FR_ERROR_INVALID_ARGUMENT, "audio needs a sample rate above 0");
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(samples[i])) {
      char at[24];
      return Fail(FR_ERROR_INVALID_ARGUMENT, {"sample ", Number(i, at), " is NaN or infinite"});
    }
  }
  return FR_OK;
}

}  // namespace

}  // namespace facerig::capi

using namespace facerig::capi;

extern "C" {

fr_status fr_speech_load_track_file(const char* path, fr_speech** out_speech) {
  return Guard([&] {
    FR_REQUIRE(out_speech, "out_speech");
    *out_speech = nullptr;
    FR_REQUIRE(path, "path");
    fr_speech speech;
    speech.line = facerig::ReadPhonemeTrack(path).line;
    return Publish(std::move(speech), out_speech);
  });
}

fr_status fr_speech_load_track_bytes(const char* json, size_t size, fr_speech** out_speech) {
  return Guard([&] {
    FR_REQUIRE(out_speech, "out_speech");
    *out_speech = nullptr;
    FR_REQUIRE(json, "json");
    if (size > facerig::kPhonemeTrackMaxFileBytes) {
      return Fail(FR_ERROR_FORMAT, "<memory>: the phoneme track is larger than 64 MiB");
    }
    fr_speech speech;
    speech.line = facerig::ParsePhonemeTrack(std::string_view(json, size)).line;
    return Publish(std::move(speech), out_speech);
  });
}

fr_status fr_speech_create(const fr_phoneme* phonemes, size_t phoneme_count, const float* samples,
                           size_t sample_count, int32_t sample_rate, fr_speech** out_speech) {
  return Guard([&] {
    FR_REQUIRE(out_speech, "out_speech");
    *out_speech = nullptr;
    if (phonemes == nullptr && phoneme_count > 0) return Fail(FR_ERROR_INVALID_ARGUMENT, "phonemes is NULL");
    if (const fr_status s = CheckAudio(samples, sample_count, sample_rate); s != FR_OK) return s;
    fr_speech speech;
    speech.line.phonemes.resize(phoneme_count);
    for (std::size_t i = 0; i < phoneme_count; ++i) {
      if (const fr_status s = FromC(phonemes[i], &speech.line.phonemes[i]); s != FR_OK) return s;
      if (i > 0 && speech.line.phonemes[i].start < speech.line.phonemes[i - 1].start) {
        char at[24];
        return Fail(FR_ERROR_INVALID_ARGUMENT, {"phoneme ", Number(i, at), " starts before the one before it"});
      }
    }
    if (sample_count > 0) speech.samples.assign(samples, samples + sample_count);
    speech.sample_rate = sample_count > 0 ? sample_rate : 0;
    return Publish(std::move(speech), out_speech);
  });
}

fr_status fr_speech_from_audio(const float* samples, size_t sample_count, int32_t sample_rate,
                               fr_speech** out_speech) {
  return Guard([&] {
    FR_REQUIRE(out_speech, "out_speech");
    *out_speech = nullptr;
    FR_REQUIRE(samples, "samples");
    if (const fr_status s = CheckAudio(samples, sample_count, sample_rate); s != FR_OK) return s;
    std::optional<facerig::SpeechLine> line =
        facerig::RoughMouthFromAudio(std::span(samples, sample_count), sample_rate);
    if (!line) {
      return Fail(FR_ERROR_INVALID_ARGUMENT, {"sample rate ", std::to_string(sample_rate),
                                              " Hz is outside what the rough mode reads (4000-384000)"});
    }
    fr_speech speech;
    speech.line = std::move(*line);
    speech.samples.assign(samples, samples + sample_count);
    speech.sample_rate = sample_rate;
    return Publish(std::move(speech), out_speech);
  });
}

fr_status fr_speech_align(const fr_speech* reference, const float* samples, size_t sample_count,
                          int32_t sample_rate, fr_alignment_fit* fit, fr_speech** out_speech) {
  return Guard([&] {
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
    if (const fr_status s = CheckAudio(samples, sample_count, sample_rate); s != FR_OK) return s;
    facerig::SpeechLine line = reference->line;
    line.sample_rate = reference->sample_rate;
    line.audio = facerig::FloatToPcm(reference->samples);
    const std::span<const float> recording(samples, sample_count);
    facerig::PhonemeAlignment alignment = facerig::AlignPhonemesToRecording(line, recording);
    if (fit != nullptr) *fit = {alignment.confidence, alignment.tempo, facerig::TranscriptFits(alignment) ? 1 : 0, 0};
    fr_speech aligned;
    aligned.line = std::move(alignment.line);
    aligned.samples.assign(recording.begin(), recording.end());
    aligned.sample_rate = sample_rate;
    return Publish(std::move(aligned), out_speech);
  });
}

void fr_speech_release(fr_speech* speech) { delete speech; }

fr_status fr_speech_phonemes(const fr_speech* speech, fr_phoneme* phonemes, size_t capacity, size_t* needed) {
  return Guard([&] {
    FR_REQUIRE(speech, "speech");
    const auto& line = speech->line.phonemes;
    if (const fr_status s = CheckCapacity(line.size(), capacity, needed, "phonemes"); s != FR_OK) return s;
    if (!line.empty()) FR_REQUIRE(phonemes, "phonemes");
    for (std::size_t i = 0; i < line.size(); ++i) phonemes[i] = ToC(line[i]);
    return FR_OK;
  });
}

fr_status fr_speech_audio(const fr_speech* speech, float* samples, size_t capacity, size_t* needed,
                          int32_t* sample_rate) {
  return Guard([&] {
    FR_REQUIRE(speech, "speech");
    if (sample_rate) *sample_rate = speech->sample_rate;
    if (const fr_status s = CheckCapacity(speech->samples.size(), capacity, needed, "samples"); s != FR_OK) return s;
    if (!speech->samples.empty()) FR_REQUIRE(samples, "samples");
    std::copy(speech->samples.begin(), speech->samples.end(), samples);
    return FR_OK;
  });
}

}  // extern "C"
