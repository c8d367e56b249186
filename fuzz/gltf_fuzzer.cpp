// glTF JSON and GLB (a .gltf that starts with "glTF" is read as binary).
#include <string>

#include "facerig/runtime/error.h"
#include "facerig/runtime/io/gltf.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    facerig::ParseGltf(facerig::fuzz::Bytes(data, size), std::string(facerig::fuzz::kFolder) + "input.gltf");
  } catch (const facerig::IoError&) {
  }
  return 0;
}
