#include "facerig/runtime/files/image_file.h"

#include <array>
#include <cstring>
#include <vector>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/input_file.h"

namespace facerig {
namespace {

constexpr std::array<std::uint8_t, 8> kPngSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};

std::uint32_t BigEndian(std::span<const std::byte> bytes, std::size_t at, std::size_t size) {
  std::uint32_t value = 0;
  for (std::size_t i = 0; i < size; ++i) value = (value << 8) | std::to_integer<std::uint32_t>(bytes[at + i]);
  return value;
}

std::uint8_t Byte(std::span<const std::byte> bytes, std::size_t at) { return std::to_integer<std::uint8_t>(bytes[at]); }

// Signature, then the IHDR chunk: length, "IHDR", width, height.
ImageHeader ProbePng(std::span<const std::byte> bytes, const std::string& path) {
  if (bytes.size() < 24) throw IoError(IoErrorKind::kTruncated, path, "the PNG ends inside its header");
  if (std::memcmp(bytes.data() + 12, "IHDR", 4) != 0) {
    throw IoError(IoErrorKind::kParse, path, "the PNG does not start with an IHDR chunk");
  }
  return {ImageFormat::kPng, BigEndian(bytes, 16, 4), BigEndian(bytes, 20, 4)};
}

// Start-of-frame markers: C0-CF except DHT (C4), JPG (C8) and DAC (CC).
bool IsStartOfFrame(std::uint8_t marker) {
  return marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
}

// Walks the segments (marker, big-endian length) up to the first frame header.
ImageHeader ProbeJpeg(std::span<const std::byte> bytes, const std::string& path) {
  std::size_t at = 2;
  while (at + 4 <= bytes.size()) {
    if (Byte(bytes, at) != 0xFF) throw IoError(IoErrorKind::kParse, path, "the JPEG has a broken segment", 0, static_cast<std::int64_t>(at));
    const std::uint8_t marker = Byte(bytes, at + 1);
    if (marker == 0xFF) {  // fill byte
      ++at;
      continue;
    }
    if (marker == 0xD9 || marker == 0xDA) break;  // end of image, or scan data before any frame
    const std::uint32_t length = BigEndian(bytes, at + 2, 2);
    if (length < 2) throw IoError(IoErrorKind::kParse, path, "the JPEG has a segment shorter than its header", 0, static_cast<std::int64_t>(at));
    if (IsStartOfFrame(marker)) {
      if (at + 9 > bytes.size()) break;
      // Length, precision, then height before width.
      return {ImageFormat::kJpeg, BigEndian(bytes, at + 7, 2), BigEndian(bytes, at + 5, 2)};
    }
    at += 2 + length;
  }
  throw IoError(IoErrorKind::kTruncated, path, "the JPEG has no frame header");
}

void CheckSize(const ImageHeader& header, const std::string& path) {
  const std::string size = std::to_string(header.width) + " x " + std::to_string(header.height);
  if (header.width == 0 || header.height == 0) throw IoError(IoErrorKind::kAbsurdCount, path, "the image is " + size);
  if (header.width > kMaxImageSide || header.height > kMaxImageSide ||
      std::uint64_t{header.width} * header.height > kMaxImagePixels) {
    throw IoError(IoErrorKind::kAbsurdCount, path,
                  "the image is " + size + " (at most " + std::to_string(kMaxImageSide) + " per side)");
  }
}

}  // namespace

ImageHeader ProbeImage(std::span<const std::byte> bytes, const std::string& path_for_errors) {
  ImageHeader header;
  if (bytes.size() >= kPngSignature.size() && std::memcmp(bytes.data(), kPngSignature.data(), kPngSignature.size()) == 0) {
    header = ProbePng(bytes, path_for_errors);
  } else if (bytes.size() >= 3 && Byte(bytes, 0) == 0xFF && Byte(bytes, 1) == 0xD8 && Byte(bytes, 2) == 0xFF) {
    header = ProbeJpeg(bytes, path_for_errors);
  } else {
    throw IoError(IoErrorKind::kBadMagic, path_for_errors, "not a PNG or JPEG image");
  }
  CheckSize(header, path_for_errors);
  return header;
}

EncodedImage MakeEncodedImage(std::span<const std::byte> bytes, std::string name, const std::string& path_for_errors) {
  const ImageHeader header = ProbeImage(bytes, path_for_errors);
  EncodedImage image{.name = std::move(name), .format = header.format, .width = header.width, .height = header.height};
  image.bytes.resize(bytes.size());
  std::memcpy(image.bytes.data(), bytes.data(), bytes.size());
  return image;
}

EncodedImage ReadImageFile(const std::filesystem::path& path) {
  const std::vector<std::byte> bytes = ReadInputFile(path, kMaxImageFileBytes);
  return MakeEncodedImage(bytes, path.filename().string(), path.string());
}

}  // namespace facerig
