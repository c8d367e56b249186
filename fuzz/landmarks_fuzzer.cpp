// Landmark JSON (landmarks.h).
#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/runtime/error.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    facerig::ParseLandmarksJson(facerig::fuzz::Text(data, size), "input.json");
  } catch (const facerig::IoError&) {
  }
  return 0;
}
