// Audio files (libsndfile from memory): WAV, FLAC, Ogg, AIFF, ...
#include "facerig/runtime/error.h"
#include "facerig/runtime/io/audio_file.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    facerig::DecodeAudio(facerig::fuzz::Bytes(data, size), "input.wav");
  } catch (const facerig::IoError&) {
  }
  return 0;
}
