// The codecs behind image_codec.h, one file each.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <opencv2/core/mat.hpp>

namespace facerig::codec {

cv::Mat DecodePng(std::span<const std::uint8_t> bytes);   // 8-bit BGRA
cv::Mat DecodeJpeg(std::span<const std::uint8_t> bytes);  // 8-bit BGR, EXIF orientation applied

// The orientation (1-8) an EXIF APP1 segment ("Exif\0\0", a TIFF header,
// IFD0) gives in its tag 0x0112; 0 when it has none or does not parse.
int ExifOrientation(std::span<const std::uint8_t> app1);
// The image as a viewer shows it for that orientation (OpenCV's own mapping).
cv::Mat Oriented(const cv::Mat& image, int orientation);

}  // namespace facerig::codec
