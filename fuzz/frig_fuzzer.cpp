// .frig rigs.
#include "facerig/runtime/error.h"
#include "facerig/runtime/io/frig.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    facerig::ParseFrig(facerig::fuzz::Bytes(data, size), "input.frig");
  } catch (const facerig::IoError&) {
  }
  return 0;
}
