// tinygltf's implementation, compiled into the module (Debian ships it as a
// shared library for the host only). Images stay encoded: the runtime's
// readers install their own image callback, so stb is not needed.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

// tinygltf's default image callbacks, which it names even when stb is left
// out: facerig's reader installs its own loader (images stay encoded) and
// its writer embeds encoded images, so these only refuse.
namespace tinygltf {
bool LoadImageData(Image*, const int, std::string* err, std::string*, int, int, const unsigned char*, int, void*) {
  if (err) *err += "facerig (WebAssembly): no built-in image decoder\n";
  return false;
}
bool WriteImageData(const std::string*, const std::string*, const Image*, bool, std::string*, void*) {
  return false;
}
}  // namespace tinygltf
