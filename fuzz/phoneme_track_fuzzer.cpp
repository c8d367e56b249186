// Phoneme-track JSON.
#include "facerig/runtime/error.h"
#include "facerig/runtime/io/phoneme_track_file.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    facerig::ParsePhonemeTrack(facerig::fuzz::Text(data, size), "input.json");
  } catch (const facerig::IoError&) {
  }
  return 0;
}
