// Image headers: ProbeImage, MakeEncodedImage and ReadImageFile on PNG and
// JPEG bytes made here (no image library), broken and oversized ones.
#include "facerig/runtime/files/image_file.h"

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "support/hostile_files.h"
#include "support/jpeg_header.h"
#include "support/test_images.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

std::span<const std::byte> AsBytes(const std::vector<std::uint8_t>& bytes) {
  return std::as_bytes(std::span(bytes.data(), bytes.size()));
}

// A PNG whose IHDR claims `width` x `height` (the pixels are an 1 x 1 image's).
std::vector<std::uint8_t> PngClaiming(std::uint32_t width, std::uint32_t height) {
  std::vector<std::uint8_t> png = test::EncodePng(1, 1, {glm::u8vec4(255)});
  for (int i = 0; i < 4; ++i) {
    png[16 + i] = static_cast<std::uint8_t>(width >> (24 - 8 * i));
    png[20 + i] = static_cast<std::uint8_t>(height >> (24 - 8 * i));
  }
  return png;
}

// The error ProbeImage throws for `bytes`; fails the test when there is none.
IoError ProbeError(const std::vector<std::uint8_t>& bytes) {
  try {
    ProbeImage(AsBytes(bytes), "bad.img");
  } catch (const IoError& error) {
    CHECK(error.path() == "bad.img");
    return error;
  }
  FAIL("no error");
  throw std::logic_error("unreachable");
}

}  // namespace

TEST_CASE("image file: PNG and JPEG headers give format and size", "[image]") {
  const ImageHeader png = ProbeImage(AsBytes(test::CheckerPng(12, 3, {255, 0, 0, 255}, {0, 0, 255, 255})), "a.png");
  CHECK(png.format == ImageFormat::kPng);
  CHECK(png.width == 12);
  CHECK(png.height == 12);
  const ImageHeader rectangle = ProbeImage(AsBytes(test::EncodePng(3, 2, std::vector<glm::u8vec4>(6))), "b.png");
  CHECK(rectangle.width == 3);
  CHECK(rectangle.height == 2);
  const ImageHeader jpeg = ProbeImage(AsBytes(test::JpegHeader(48, 32)), "c.jpg");
  CHECK(jpeg.format == ImageFormat::kJpeg);
  CHECK(jpeg.width == 48);
  CHECK(jpeg.height == 32);
  // Fill bytes before a marker are allowed.
  std::vector<std::uint8_t> filled = test::JpegHeader(5, 7);
  filled.insert(filled.begin() + 20, {0xFF, 0xFF});
  CHECK(ProbeImage(AsBytes(filled), "d.jpg").width == 5);
  // The largest sizes the caps allow.
  CHECK(ProbeImage(AsBytes(PngClaiming(kMaxImageSide, 8192)), "e.png").width == kMaxImageSide);
  CHECK(ProbeImage(AsBytes(test::JpegHeader(8192, kMaxImageSide)), "f.jpg").height == kMaxImageSide);
}

TEST_CASE("image file: bad magic, truncated headers, zero and oversized images are refused", "[image][malformed]") {
  CHECK(ProbeError({}).kind() == IoErrorKind::kBadMagic);
  CHECK(ProbeError({'G', 'I', 'F', '8', '9', 'a', 1, 0, 1, 0}).kind() == IoErrorKind::kBadMagic);
  CHECK(ProbeError({0xFF, 0xD8}).kind() == IoErrorKind::kBadMagic);
  std::vector<std::uint8_t> png = test::CheckerPng(4, 1, {0, 0, 0, 255}, {0, 0, 0, 255});
  png.resize(20);  // inside IHDR
  CHECK(ProbeError(png).kind() == IoErrorKind::kTruncated);
  std::vector<std::uint8_t> not_ihdr = test::CheckerPng(4, 1, {0, 0, 0, 255}, {0, 0, 0, 255});
  std::memcpy(not_ihdr.data() + 12, "IDAT", 4);
  CHECK(ProbeError(not_ihdr).kind() == IoErrorKind::kParse);
  // A JPEG cut before its frame header, one without any, one with a broken segment.
  std::vector<std::uint8_t> jpeg = test::JpegHeader(48, 32);
  jpeg.resize(22);
  CHECK(ProbeError(jpeg).kind() == IoErrorKind::kTruncated);
  CHECK(ProbeError({0xFF, 0xD8, 0xFF, 0xD9}).kind() == IoErrorKind::kTruncated);
  std::vector<std::uint8_t> broken = test::JpegHeader(48, 32);
  broken[20] = 0x00;
  CHECK(ProbeError(broken).kind() == IoErrorKind::kParse);
  std::vector<std::uint8_t> short_segment = test::JpegHeader(48, 32);
  short_segment[4] = 0;
  short_segment[5] = 1;
  CHECK(ProbeError(short_segment).kind() == IoErrorKind::kParse);
  // Sizes: zero, a side over the cap, too many pixels, and a 2 GB claim.
  CHECK(ProbeError(PngClaiming(0, 16)).kind() == IoErrorKind::kAbsurdCount);
  CHECK(ProbeError(test::JpegHeader(16, 0)).kind() == IoErrorKind::kAbsurdCount);
  CHECK(ProbeError(PngClaiming(kMaxImageSide + 1, 1)).kind() == IoErrorKind::kAbsurdCount);
  CHECK(ProbeError(PngClaiming(kMaxImageSide, kMaxImageSide)).kind() == IoErrorKind::kAbsurdCount);
  const IoError huge = ProbeError(PngClaiming(0x7FFFFFFF, 0x7FFFFFFF));
  CHECK(huge.kind() == IoErrorKind::kAbsurdCount);
  CHECK(huge.message().size() < 100);
}

TEST_CASE("image file: MakeEncodedImage keeps the bytes, ReadImageFile reads regular files only", "[image]") {
  const std::vector<std::uint8_t> png = test::CheckerPng(8, 2, {255, 255, 255, 255}, {0, 0, 0, 255});
  const EncodedImage made = MakeEncodedImage(AsBytes(png), "skin.png", "mem");
  CHECK(made.name == "skin.png");
  CHECK(made.bytes == png);
  CHECK(made.width == 8);

  const fs::path folder = test::OutputPath("image_file");
  fs::remove_all(folder);
  fs::create_directories(folder);
  const std::vector<std::uint8_t> jpeg = test::JpegHeader(64, 16);
  WriteFileAtomically(folder / "face.jpg", AsBytes(jpeg));
  const EncodedImage read = ReadImageFile(folder / "face.jpg");
  CHECK(read.name == "face.jpg");
  CHECK(read.format == ImageFormat::kJpeg);
  CHECK(read.bytes == jpeg);

  // An empty file, a directory, a FIFO, and a file over the byte cap (sparse).
  WriteFileAtomically(folder / "empty.png", std::string_view());
  CHECK_THROWS_AS(ReadImageFile(folder / "empty.png"), IoError);
  CHECK_THROWS_AS(ReadImageFile(folder), IoError);
  test::MakeFifo(folder / "pipe.png");
  const std::string fifo_error = test::ErrorWithoutHanging(folder / "pipe.png", [&] { ReadImageFile(folder / "pipe.png"); });
  CHECK(fifo_error.find("pipe.png") != std::string::npos);
  CHECK(fifo_error.find("FIFO") != std::string::npos);
  WriteFileAtomically(folder / "huge.png", AsBytes(png));
  fs::resize_file(folder / "huge.png", kMaxImageFileBytes + 1);
  try {
    ReadImageFile(folder / "huge.png");
    FAIL("no error");
  } catch (const IoError& error) {
    CHECK(error.kind() == IoErrorKind::kAbsurdCount);
    CHECK(std::string(error.what()).find("huge.png") != std::string::npos);
  }
  fs::remove(folder / "huge.png");
}

}  // namespace facerig
