#include "facerig/offline/render/png_encode.h"

#include <utility>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "facerig/offline/error.h"
#include "facerig/offline/io/image_codec.h"

namespace facerig {

EncodedImage EncodePng(std::span<const std::uint8_t> pixels, int width, int height, int channels,
                       std::string name, std::optional<int> compression) {
  if (width <= 0 || height <= 0 || (channels != 3 && channels != 4) ||
      pixels.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * static_cast<std::size_t>(channels)) {
    throw InvalidInputError("PNG encoding: the pixels do not match the image size", name);
  }
  const cv::Mat rgb(height, width, channels == 4 ? CV_8UC4 : CV_8UC3, const_cast<std::uint8_t*>(pixels.data()));
  cv::Mat bgr;  // OpenCV's channel order
  cv::cvtColor(rgb, bgr, channels == 4 ? cv::COLOR_RGBA2BGRA : cv::COLOR_RGB2BGR);
  EncodedImage image{.name = std::move(name), .format = ImageFormat::kPng, .width = static_cast<std::uint32_t>(width),
                     .height = static_cast<std::uint32_t>(height)};
  try {
    image.bytes = EncodePngBytes(bgr, compression);
  } catch (const InvalidInputError& error) {
    throw InvalidInputError(error.what(), image.name);
  }
  return image;
}

}  // namespace facerig
