// glTF JSON and GLB (a .gltf that starts with "glTF" is read as binary), as a
// rig and as a Mesh (materials, UVs, parts).
#include <string>

#include "facerig/runtime/error.h"
#include "facerig/runtime/io/gltf.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = std::string(facerig::fuzz::kFolder) + "input.gltf";
  try {
    facerig::ParseGltf(facerig::fuzz::Bytes(data, size), path);
  } catch (const facerig::IoError&) {
  }
  try {
    facerig::ParseGltfMesh(facerig::fuzz::Bytes(data, size), path);
  } catch (const facerig::IoError&) {
  }
  return 0;
}
