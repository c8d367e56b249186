// Photographs read through the project's image reader and decoded by OpenCV.
#include "facerig/offline/photo/image.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <opencv2/imgproc.hpp>

#include "facerig/offline/error.h"
#include "facerig/offline/io/image_codec.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/files/image_file.h"

namespace facerig {
namespace {

std::string SizeText(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

// 8-bit BGR, whatever the file held: grey, palette and 16-bit images
// converted, alpha dropped, a JPEG's EXIF orientation applied.
cv::Mat DecodeBgr(const EncodedImage& encoded, const std::string& path) {
  try {
    return DecodeImageBytes(encoded.bytes, DecodedChannels::kBgr);
  } catch (const InvalidInputError& error) {
    throw IoError(IoErrorKind::kParse, path, error.what());
  }
}

// INTER_AREA averages the pixels each output pixel covers: no aliasing.
cv::Mat Downscaled(const cv::Mat& bgr, int max_side, float& scale) {
  const int longer = std::max(bgr.cols, bgr.rows);
  if (longer <= max_side) return bgr;
  scale = static_cast<float>(max_side) / static_cast<float>(longer);
  const int width = std::max(1, static_cast<int>(std::lround(static_cast<float>(bgr.cols) * scale)));
  const int height = std::max(1, static_cast<int>(std::lround(static_cast<float>(bgr.rows) * scale)));
  cv::Mat smaller;
  cv::resize(bgr, smaller, cv::Size(width, height), 0.0, 0.0, cv::INTER_AREA);
  return smaller;
}

RgbImage ToRgb(const cv::Mat& bgr, bool& grey) {
  RgbImage rgb;
  rgb.width = bgr.cols;
  rgb.height = bgr.rows;
  rgb.pixels.resize(static_cast<std::size_t>(bgr.cols) * static_cast<std::size_t>(bgr.rows) * 3);
  grey = true;
  std::size_t i = 0;
  for (int y = 0; y < bgr.rows; ++y) {
    const cv::Vec3b* row = bgr.ptr<cv::Vec3b>(y);
    for (int x = 0; x < bgr.cols; ++x, i += 3) {
      const cv::Vec3b c = row[x];
      rgb.pixels[i] = c[2], rgb.pixels[i + 1] = c[1], rgb.pixels[i + 2] = c[0];
      grey = grey && c[0] == c[1] && c[1] == c[2];
    }
  }
  return rgb;
}

void CheckParams(const PhotoReadParams& params) {
  if (params.max_side < 16) {
    throw InvalidInputError("photo: max_side must be at least 16", "max_side", std::to_string(params.max_side));
  }
}

Photo DecodeEncoded(const EncodedImage& encoded, const std::string& path, const PhotoReadParams& params) {
  if (std::uint64_t{encoded.width} * encoded.height > params.max_pixels) {
    throw IoError(IoErrorKind::kAbsurdCount, path,
                  "the image has " + SizeText(static_cast<int>(encoded.width), static_cast<int>(encoded.height)) +
                      " pixels, more than the " + std::to_string(params.max_pixels) + " allowed");
  }
  const cv::Mat bgr = DecodeBgr(encoded, path);
  // The decoder follows the data, not the probed header: check what it made.
  if (static_cast<std::uint64_t>(bgr.cols) * static_cast<std::uint64_t>(bgr.rows) > params.max_pixels) {
    throw IoError(IoErrorKind::kAbsurdCount, path, "the image decodes to " + SizeText(bgr.cols, bgr.rows) + " pixels, more than allowed");
  }
  Photo photo;
  photo.original_width = bgr.cols;
  photo.original_height = bgr.rows;
  const cv::Mat fitted = Downscaled(bgr, params.max_side, photo.scale);
  photo.image = ToRgb(fitted, photo.grey);
  if (fitted.cols != bgr.cols || fitted.rows != bgr.rows) {
    photo.notes.push_back("downscaled from " + SizeText(bgr.cols, bgr.rows) + " to " +
                          SizeText(fitted.cols, fitted.rows) + " (at most " + std::to_string(params.max_side) +
                          " px a side)");
  }
  if (photo.grey) photo.notes.push_back("a grey-scale image: read as RGB; the texture will have no colour");
  return photo;
}

}  // namespace

Photo ReadPhoto(const std::filesystem::path& path, const PhotoReadParams& params) {
  CheckParams(params);
  return DecodeEncoded(ReadImageFile(path), path.string(), params);
}

Photo DecodePhoto(std::span<const std::byte> bytes, const std::string& name, const PhotoReadParams& params) {
  CheckParams(params);
  return DecodeEncoded(MakeEncodedImage(bytes, name, name), name, params);
}

}  // namespace facerig
