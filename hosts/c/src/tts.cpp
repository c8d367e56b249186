// libfacerig_espeak: espeak-ng speech and recorded-speech alignment, handed
// to libfacerig as fr_speech handles through its public ABI (fr_speech_create),
// so the two libraries share no C++ objects.
#include <memory>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "boundary.h"
#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/runtime/alignment/phoneme_alignment.h"
#include "facerig/runtime/io/audio_file.h"
#include "facerig_tts.h"
#include "handles.h"

namespace facerig::capi {
namespace {

// One source for the process (espeak-ng is one engine anyway), made on first use.
EspeakPhonemeSource& Source() {
  static std::mutex mutex;
  static std::unique_ptr<EspeakPhonemeSource> source;
  const std::lock_guard lock(mutex);
  if (!source) source = std::make_unique<EspeakPhonemeSource>();
  return *source;
}

std::vector<float> PcmToFloat(const std::vector<std::int16_t>& pcm) {
  std::vector<float> samples(pcm.size());
  for (std::size_t i = 0; i < pcm.size(); ++i) samples[i] = static_cast<float>(pcm[i]) / 32768.0f;
  return samples;
}

fr_status MakeSpeech(const std::vector<Phoneme>& phonemes, const std::vector<float>& samples, int sample_rate,
                     fr_speech** out_speech) {
  std::vector<fr_phoneme> converted(phonemes.size());
  for (std::size_t i = 0; i < phonemes.size(); ++i) converted[i] = ToC(phonemes[i]);
  return fr_speech_create(converted.data(), converted.size(), samples.empty() ? nullptr : samples.data(),
                          samples.size(), samples.empty() ? 0 : sample_rate, out_speech);
}

// The callbacks of fr_tts_synthesize_streaming as a SpeechStreamReceiver;
// a callback's "stop" throws Stopped, which aborts espeak-ng's line.
class CallbackReceiver final : public SpeechStreamReceiver {
 public:
  struct Stopped : std::runtime_error {
    Stopped() : std::runtime_error("the line was stopped by a callback") {}
  };

  CallbackReceiver(std::int32_t* sample_rate, fr_tts_audio_fn on_audio, fr_tts_phoneme_fn on_phoneme, void* user)
      : sample_rate_(sample_rate), on_audio_(on_audio), on_phoneme_(on_phoneme), user_(user) {}

  void OnStart(int sample_rate) override {
    if (sample_rate_) *sample_rate_ = sample_rate;
  }
  void OnAudio(std::span<const std::int16_t> samples) override {
    if (!on_audio_) return;
    chunk_.resize(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) chunk_[i] = static_cast<float>(samples[i]) / 32768.0f;
    if (on_audio_(user_, chunk_.data(), chunk_.size()) != 0) throw Stopped();
  }
  void OnPhoneme(const Phoneme& phoneme) override {
    const fr_phoneme converted = ToC(phoneme);
    if (on_phoneme_ && on_phoneme_(user_, &converted) != 0) throw Stopped();
  }
  void OnEnd() override {}

 private:
  std::int32_t* sample_rate_;
  fr_tts_audio_fn on_audio_;
  fr_tts_phoneme_fn on_phoneme_;
  void* user_;
  std::vector<float> chunk_;
};

}  // namespace
}  // namespace facerig::capi

using namespace facerig::capi;

extern "C" {

fr_status fr_tts_synthesize(const char* text, const char* voice, fr_speech** out_speech) {
  return Guard([&] {
    FR_REQUIRE(out_speech, "out_speech");
    *out_speech = nullptr;
    FR_REQUIRE(text, "text");
    FR_REQUIRE(voice, "voice");
    const facerig::SpeechLine line = Source().Synthesize(text, voice);
    return MakeSpeech(line.phonemes, PcmToFloat(line.audio), line.sample_rate, out_speech);
  });
}

fr_status fr_tts_synthesize_streaming(const char* text, const char* voice, int32_t* sample_rate,
                                      fr_tts_audio_fn on_audio, fr_tts_phoneme_fn on_phoneme, void* user_data) {
  return Guard([&] {
    FR_REQUIRE(text, "text");
    FR_REQUIRE(voice, "voice");
    CallbackReceiver receiver(sample_rate, on_audio, on_phoneme, user_data);
    try {
      Source().SynthesizeStreaming(text, voice, receiver);
    } catch (const CallbackReceiver::Stopped& stopped) {
      return Fail(FR_ERROR_CANCELLED, stopped.what());
    }
    return FR_OK;
  });
}

fr_status fr_tts_align(const float* samples, size_t sample_count, int32_t sample_rate, const char* transcript,
                       const char* voice, fr_speech** out_speech) {
  return Guard([&] {
    FR_REQUIRE(out_speech, "out_speech");
    *out_speech = nullptr;
    FR_REQUIRE(samples, "samples");
    FR_REQUIRE(transcript, "transcript");
    FR_REQUIRE(voice, "voice");
    if (sample_count == 0) return Fail(FR_ERROR_INVALID_ARGUMENT, "the recording has no samples");
    const std::span<const float> recording(samples, sample_count);
    const facerig::SpeechLine reference = Source().Synthesize(transcript, voice);
    if (reference.phonemes.empty() || reference.audio.empty()) {
      return Fail(FR_ERROR_SPEECH, "the transcript gives no speech to align");
    }
    const std::vector<float> resampled = facerig::ResampleAudio(recording, sample_rate, reference.sample_rate);
    const facerig::PhonemeAlignment alignment = facerig::AlignPhonemesToRecording(reference, resampled);
    return MakeSpeech(alignment.line.phonemes, std::vector<float>(recording.begin(), recording.end()), sample_rate,
                      out_speech);
  });
}

fr_status fr_tts_voices(char* buffer, size_t capacity, size_t* needed) {
  return Guard([&] {
    std::string list;
    for (const std::string& voice : Source().Voices()) list += voice + "\n";
    return CopyString(list, buffer, capacity, needed);
  });
}

}  // extern "C"
