// Photographs for `facerig photo`: DecodePhoto (the image reader's probe,
// then OpenCV's PNG and JPEG decoders, colour conversion and downscaling)
// must return an RGB image as large as it says, or throw IoError.
#include <cstdlib>

#include "facerig/offline/photo/image.h"
#include "facerig/runtime/error.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // A small cap on pixels and side: a few kilobytes of PNG can ask for a huge
  // image, and decoding it would spend the run's time on one input.
  const facerig::PhotoReadParams params{.max_side = 64, .max_pixels = std::uint64_t{1} << 20};
  try {
    const facerig::Photo photo = facerig::DecodePhoto(facerig::fuzz::Bytes(data, size), "input.png", params);
    const facerig::RgbImage& image = photo.image;
    if (image.width <= 0 || image.height <= 0 || image.width > params.max_side || image.height > params.max_side ||
        image.pixels.size() != 3 * static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) ||
        photo.original_width < image.width || photo.original_height < image.height) {
      std::abort();
    }
  } catch (const facerig::IoError&) {
  }
  return 0;
}
