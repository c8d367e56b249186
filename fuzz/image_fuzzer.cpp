// PNG and JPEG headers: ProbeImage must return a size within the caps or
// throw IoError.
#include <cstdlib>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/image_file.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const facerig::ImageHeader header = facerig::ProbeImage(facerig::fuzz::Bytes(data, size), "input.png");
    if (header.width == 0 || header.height == 0 || header.width > facerig::kMaxImageSide ||
        header.height > facerig::kMaxImageSide ||
        std::uint64_t{header.width} * header.height > facerig::kMaxImagePixels) {
      std::abort();
    }
  } catch (const facerig::IoError&) {
  }
  return 0;
}
