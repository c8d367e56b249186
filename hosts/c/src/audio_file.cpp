// Recordings read from files (libsndfile, through runtime_io's bounded reader)
// as speech lines holding audio only. Apart from speech.cpp because the
// WebAssembly module decodes audio in the page and leaves this file out.
#include <memory>
#include <utility>

#include "boundary.h"
#include "facerig/runtime/io/audio_file.h"
#include "handles.h"

using namespace facerig::capi;

extern "C" {

fr_status fr_speech_load_audio_file(const char* path, fr_speech** out_speech) {
  return Guard([&] {
    FR_REQUIRE(out_speech, "out_speech");
    *out_speech = nullptr;
    FR_REQUIRE(path, "path");
    facerig::AudioClip clip = facerig::ReadAudioFile(path);
    auto speech = std::make_unique<fr_speech>();
    speech->samples = std::move(clip.samples);
    speech->sample_rate = clip.sample_rate;
    *out_speech = speech.release();
    return FR_OK;
  });
}

}  // extern "C"
