// Photographs as `facerig photo` reads them (photo_image.h).
#include "facerig/offline/photo/image.h"

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>

#include <catch2/catch.hpp>

#include "facerig/offline/error.h"
#include "facerig/runtime/error.h"
#include "support/test_meshes.h"
#include "offline/cli/output_set_files.h"

namespace facerig {
namespace {

RgbImage Gradient(int width, int height, bool grey) {
  RgbImage image{width, height, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3)};
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      std::uint8_t* p = &image.pixels[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x))];
      p[0] = static_cast<std::uint8_t>(x % 256);
      p[1] = grey ? p[0] : static_cast<std::uint8_t>(y % 256);
      p[2] = grey ? p[0] : 90;
    }
  }
  return image;
}

}  // namespace

TEST_CASE("photo image: a large photo is downscaled to 2048 px on its longer side, with a note", "[photo_image]") {
  const std::filesystem::path path = test::FreshOutputFolder("photo_image_large") / "wide.png";
  WritePng(path, Gradient(2600, 1000, false));
  const Photo photo = ReadPhoto(path);
  CHECK(photo.original_width == 2600);
  CHECK(photo.original_height == 1000);
  CHECK(photo.image.width == 2048);
  CHECK(photo.image.height == 788);
  CHECK(photo.scale == Approx(2048.0 / 2600.0));
  CHECK_FALSE(photo.grey);
  REQUIRE(photo.notes.size() == 1);
  CHECK(photo.notes[0] == "downscaled from 2600x1000 to 2048x788 (at most 2048 px a side)");
}

TEST_CASE("photo image: a grey photo is read as RGB with a note, and bad files are refused", "[photo_image]") {
  const std::filesystem::path folder = test::FreshOutputFolder("photo_image_grey");
  WritePng(folder / "grey.png", Gradient(64, 48, true));
  const Photo photo = ReadPhoto(folder / "grey.png");
  CHECK(photo.grey);
  CHECK(photo.image.width == 64);
  CHECK(photo.scale == 1.0f);
  REQUIRE(photo.notes.size() == 1);
  CHECK(photo.notes[0].find("grey-scale") != std::string::npos);
  // A PNG header over an image that does not decode.
  const std::string png = test::ReadText(folder / "grey.png");
  test::WriteText(folder / "broken.png", png.substr(0, 40));
  CHECK_THROWS_AS(ReadPhoto(folder / "broken.png"), IoError);
  test::WriteText(folder / "text.jpg", "not a picture");
  CHECK_THROWS_WITH(ReadPhoto(folder / "text.jpg"), Catch::Contains("text.jpg"));
  CHECK_THROWS_AS(ReadPhoto(folder / "missing.png"), IoError);
  CHECK_THROWS_AS(ReadPhoto(folder / "grey.png", {.max_side = 4}), InvalidInputError);
}

}  // namespace facerig

namespace facerig {

TEST_CASE("photo image: bytes in memory decode as the file does, and more pixels than max_pixels are refused", "[photo_image]") {
  const std::filesystem::path path = test::FreshOutputFolder("photo_image_bytes") / "wide.png";
  WritePng(path, Gradient(300, 100, false));
  const std::string text = test::ReadText(path);
  const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(text.data()), text.size());
  const Photo from_file = ReadPhoto(path, {.max_side = 120});
  const Photo from_bytes = DecodePhoto(bytes, "wide.png", {.max_side = 120});
  CHECK(from_bytes.image.width == 120);
  CHECK(from_bytes.image.height == 40);
  CHECK(from_bytes.image.pixels == from_file.image.pixels);
  CHECK(from_bytes.notes == from_file.notes);
  // 30 000 pixels against a cap of 20 000: refused before decoding, naming the file.
  CHECK_THROWS_WITH(DecodePhoto(bytes, "wide.png", {.max_pixels = 20000}), Catch::Contains("wide.png"));
  CHECK_THROWS_AS(ReadPhoto(path, {.max_pixels = 20000}), IoError);
  CHECK_THROWS_AS(DecodePhoto(bytes.first(30), "cut.png"), IoError);
}

}  // namespace facerig
