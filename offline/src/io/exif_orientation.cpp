// The one EXIF tag a photo reader needs: how the camera was held.
#include "io/image_codec_internal.h"

#include <cstring>

#include <opencv2/core.hpp>

namespace facerig::codec {
namespace {

constexpr std::uint16_t kOrientationTag = 0x0112;

struct TiffReader {
  std::span<const std::uint8_t> tiff;
  bool little_endian = true;

  bool Has(std::size_t offset, std::size_t size) const { return offset <= tiff.size() && size <= tiff.size() - offset; }
  std::uint16_t U16(std::size_t offset) const {
    const std::uint16_t a = tiff[offset], b = tiff[offset + 1];
    return little_endian ? static_cast<std::uint16_t>(a | b << 8) : static_cast<std::uint16_t>(a << 8 | b);
  }
  std::uint32_t U32(std::size_t offset) const {
    const std::uint32_t a = U16(offset), b = U16(offset + 2);
    return little_endian ? a | b << 16 : a << 16 | b;
  }
};

}  // namespace

int ExifOrientation(std::span<const std::uint8_t> app1) {
  constexpr std::uint8_t kExifId[] = {'E', 'x', 'i', 'f', 0, 0};
  if (app1.size() < sizeof(kExifId) + 8 || std::memcmp(app1.data(), kExifId, sizeof(kExifId)) != 0) return 0;
  TiffReader reader{.tiff = app1.subspan(sizeof(kExifId))};
  if (reader.tiff[0] == 'I' && reader.tiff[1] == 'I') {
    reader.little_endian = true;
  } else if (reader.tiff[0] == 'M' && reader.tiff[1] == 'M') {
    reader.little_endian = false;
  } else {
    return 0;
  }
  const std::size_t ifd = reader.U32(4);
  if (!reader.Has(ifd, 2)) return 0;
  const std::size_t entries = reader.U16(ifd);
  for (std::size_t i = 0; i < entries; ++i) {
    const std::size_t entry = ifd + 2 + 12 * i;
    if (!reader.Has(entry, 12)) return 0;
    if (reader.U16(entry) != kOrientationTag) continue;
    const std::uint16_t value = reader.U16(entry + 8);  // a SHORT, left-aligned in the value field
    return value >= 1 && value <= 8 ? value : 0;
  }
  return 0;
}

cv::Mat Oriented(const cv::Mat& image, int orientation) {
  cv::Mat out;
  switch (orientation) {
    case 2: cv::flip(image, out, 1); return out;
    case 3: cv::flip(image, out, -1); return out;
    case 4: cv::flip(image, out, 0); return out;
    case 5: cv::transpose(image, out); return out;
    case 6: cv::transpose(image, out); cv::flip(out, out, 1); return out;
    case 7: cv::transpose(image, out); cv::flip(out, out, -1); return out;
    case 8: cv::transpose(image, out); cv::flip(out, out, 0); return out;
    default: return image;
  }
}

}  // namespace facerig::codec
