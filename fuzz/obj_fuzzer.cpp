// OBJ meshes.
#include "facerig/runtime/error.h"
#include "facerig/runtime/io/obj.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    facerig::ParseObj(facerig::fuzz::Text(data, size), "input.obj");
  } catch (const facerig::IoError&) {
  }
  return 0;
}
