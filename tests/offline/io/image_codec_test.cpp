// PNG and JPEG bytes through libpng and libjpeg-turbo (io/image_codec.h).
#include "facerig/offline/io/image_codec.h"

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <jpeglib.h>
#include <opencv2/core.hpp>

#include "facerig/offline/error.h"

namespace facerig {
namespace {

// Smooth colours with a different value in every pixel and channel.
cv::Mat Pattern(int width, int height, int channels) {
  cv::Mat image(height, width, CV_8UC(channels));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < channels; ++c) image.ptr<std::uint8_t>(y)[x * channels + c] = static_cast<std::uint8_t>(x * 3 + y * 5 + c * 60);
    }
  }
  return image;
}

// A baseline JPEG of an 8-bit BGR image (libjpeg-turbo, quality 95).
std::vector<std::uint8_t> EncodeJpeg(const cv::Mat& bgr) {
  jpeg_compress_struct info;
  jpeg_error_mgr errors;
  info.err = jpeg_std_error(&errors);
  jpeg_create_compress(&info);
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&info, &buffer, &size);
  info.image_width = static_cast<JDIMENSION>(bgr.cols);
  info.image_height = static_cast<JDIMENSION>(bgr.rows);
  info.input_components = 3;
  info.in_color_space = JCS_EXT_BGR;
  jpeg_set_defaults(&info);
  jpeg_set_quality(&info, 95, TRUE);
  jpeg_start_compress(&info, TRUE);
  while (info.next_scanline < info.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(bgr.ptr<std::uint8_t>(static_cast<int>(info.next_scanline)));
    jpeg_write_scanlines(&info, &row, 1);
  }
  jpeg_finish_compress(&info);
  jpeg_destroy_compress(&info);
  std::vector<std::uint8_t> bytes(buffer, buffer + size);
  std::free(buffer);
  return bytes;
}

// The JPEG with an EXIF segment (big- or little-endian TIFF) giving `orientation`, after its SOI marker.
std::vector<std::uint8_t> WithExifOrientation(std::vector<std::uint8_t> jpeg, std::uint16_t orientation, bool big_endian) {
  const auto u16 = [&](std::uint16_t v) -> std::vector<std::uint8_t> {
    return big_endian ? std::vector<std::uint8_t>{std::uint8_t(v >> 8), std::uint8_t(v)}
                      : std::vector<std::uint8_t>{std::uint8_t(v), std::uint8_t(v >> 8)};
  };
  std::vector<std::uint8_t> tiff = big_endian ? std::vector<std::uint8_t>{'M', 'M', 0, 42, 0, 0, 0, 8}
                                              : std::vector<std::uint8_t>{'I', 'I', 42, 0, 8, 0, 0, 0};
  // One IFD entry: tag 0x0112, type SHORT, a 4-byte count of 1, the value padded to 4 bytes; no next IFD.
  const std::vector<std::uint8_t> count_high = u16(0), count_low = u16(1);
  for (const auto& part : {u16(1), u16(0x0112), u16(3), big_endian ? count_high : count_low,
                           big_endian ? count_low : count_high, u16(orientation), u16(0), u16(0), u16(0)}) {
    tiff.insert(tiff.end(), part.begin(), part.end());
  }
  std::vector<std::uint8_t> segment = {0xFF, 0xE1, 0, 0, 'E', 'x', 'i', 'f', 0, 0};
  segment.insert(segment.end(), tiff.begin(), tiff.end());
  const std::size_t length = segment.size() - 2;
  segment[2] = std::uint8_t(length >> 8);
  segment[3] = std::uint8_t(length);
  jpeg.insert(jpeg.begin() + 2, segment.begin(), segment.end());
  return jpeg;
}

}  // namespace

TEST_CASE("image codec: PNG round trips keep every pixel, BGR and BGRA, fast and at each level", "[image_codec]") {
  for (const int channels : {3, 4}) {
    const cv::Mat image = Pattern(37, 23, channels);
    for (const std::optional<int> level : {std::optional<int>(), std::optional<int>(0), std::optional<int>(9)}) {
      const std::vector<std::uint8_t> png = EncodePngBytes(image, level);
      const cv::Mat back = DecodeImageBytes(png, channels == 4 ? DecodedChannels::kBgra : DecodedChannels::kBgr);
      REQUIRE(back.size() == image.size());
      REQUIRE(back.type() == image.type());
      CHECK(cv::norm(back, image, cv::NORM_INF) == 0.0);
    }
  }
  // Alpha dropped on request, added as opaque where the file has none.
  const cv::Mat bgra = Pattern(8, 8, 4);
  const cv::Mat bgr = DecodeImageBytes(EncodePngBytes(bgra), DecodedChannels::kBgr);
  CHECK(bgr.channels() == 3);
  CHECK(bgr.at<cv::Vec3b>(2, 3) == cv::Vec3b(bgra.at<cv::Vec4b>(2, 3)[0], bgra.at<cv::Vec4b>(2, 3)[1], bgra.at<cv::Vec4b>(2, 3)[2]));
  const cv::Mat opaque = DecodeImageBytes(EncodePngBytes(Pattern(8, 8, 3)), DecodedChannels::kBgra);
  CHECK(opaque.at<cv::Vec4b>(5, 5)[3] == 255);
}

TEST_CASE("image codec: a JPEG decodes close to its pixels, turned as its EXIF orientation says", "[image_codec]") {
  // 32x16: a white 8x8 block at the stored image's top-left corner on grey.
  cv::Mat stored(16, 32, CV_8UC3, cv::Scalar(100, 100, 100));
  stored(cv::Rect(0, 0, 8, 8)).setTo(cv::Scalar(255, 255, 255));
  const std::vector<std::uint8_t> jpeg = EncodeJpeg(stored);
  const cv::Mat plain = DecodeImageBytes(jpeg, DecodedChannels::kBgr);
  REQUIRE(plain.size() == stored.size());
  CHECK(cv::norm(plain, stored, cv::NORM_INF) < 12.0);
  // Where a viewer shows the stored top-left corner for each EXIF orientation (EXIF 2.3, tag 0x0112).
  struct Case {
    std::uint16_t orientation;
    bool right, bottom;
  };
  for (const Case c : {Case{1, false, false}, Case{2, true, false}, Case{3, true, true}, Case{4, false, true},
                       Case{5, false, false}, Case{6, true, false}, Case{7, true, true}, Case{8, false, true}}) {
    for (const bool big_endian : {false, true}) {
      INFO("orientation " << c.orientation << (big_endian ? ", big-endian" : ", little-endian"));
      const cv::Mat shown = DecodeImageBytes(WithExifOrientation(jpeg, c.orientation, big_endian), DecodedChannels::kBgr);
      const bool turned = c.orientation >= 5;
      REQUIRE(shown.cols == (turned ? 16 : 32));
      REQUIRE(shown.rows == (turned ? 32 : 16));
      const int x = c.right ? shown.cols - 4 : 3, y = c.bottom ? shown.rows - 4 : 3;
      CHECK(shown.at<cv::Vec3b>(y, x)[1] > 230);  // the white block
      CHECK(shown.at<cv::Vec3b>(shown.rows - 1 - y, shown.cols - 1 - x)[1] < 120);  // grey across
    }
  }
}

TEST_CASE("image codec: bytes that do not decode are refused with a message", "[image_codec]") {
  const std::vector<std::uint8_t> png = EncodePngBytes(Pattern(16, 16, 3));
  const std::vector<std::uint8_t> jpeg = EncodeJpeg(Pattern(16, 16, 3));
  CHECK_THROWS_WITH(DecodeImageBytes(std::vector<std::uint8_t>(png.begin(), png.begin() + 60), DecodedChannels::kBgr),
                    Catch::Contains("PNG"));
  CHECK_THROWS_WITH(DecodeImageBytes(std::vector<std::uint8_t>(jpeg.begin(), jpeg.begin() + 30), DecodedChannels::kBgr),
                    Catch::Contains("JPEG"));
  CHECK_THROWS_WITH(DecodeImageBytes(std::vector<std::uint8_t>{'G', 'I', 'F', '8', '9', 'a'}, DecodedChannels::kBgr),
                    Catch::Contains("neither PNG nor JPEG"));
  CHECK_THROWS_AS(DecodeImageBytes({}, DecodedChannels::kBgr), InvalidInputError);
  CHECK_THROWS_AS(EncodePngBytes(cv::Mat(4, 4, CV_16UC3)), InvalidInputError);
}

}  // namespace facerig
