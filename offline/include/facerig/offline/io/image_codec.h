// PNG and JPEG bytes to and from OpenCV images, through libpng and
// libjpeg-turbo directly. OpenCV's own codec module (imgcodecs) is not used:
// Debian builds it against GDAL, HDF5, Poppler and GDCM, about 140 shared
// libraries that every process linking it loads at start-up (0.2 s of CPU).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <opencv2/core/mat.hpp>

namespace facerig {

enum class DecodedChannels : std::uint8_t {
  kBgr,   // 8-bit BGR: grey, palette and 16-bit converted, alpha dropped
  kBgra,  // 8-bit BGRA: alpha kept (255 where the file has none)
};

// Decodes a PNG or a JPEG (told apart by their signatures) into 8-bit
// pixels; a JPEG's EXIF orientation is applied, as cameras store it.
// \throw InvalidInputError naming what does not decode.
cv::Mat DecodeImageBytes(std::span<const std::uint8_t> bytes, DecodedChannels channels);

// An 8-bit BGR or BGRA image as PNG bytes (RGB or RGBA) at zlib level
// `compression` (0-9); without one, fast: level 1, the "sub" filter and
// run-length matches (OpenCV's default, which the earlier files had).
// \throw InvalidInputError when the image is not 8-bit with 3 or 4 channels.
std::vector<std::uint8_t> EncodePngBytes(const cv::Mat& bgr, std::optional<int> compression = std::nullopt);

}  // namespace facerig
