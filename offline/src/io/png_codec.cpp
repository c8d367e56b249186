// PNG through libpng 1.6's simplified API to read (it reports errors in the
// image struct, no longjmp) and its full API to write (the simplified writer
// has no compression level).
#include "facerig/offline/io/image_codec.h"
#include "io/image_codec_internal.h"

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>

#include <png.h>
#include <zlib.h>

#include "facerig/offline/error.h"
#include "facerig/runtime/files/image_file.h"

namespace facerig::codec {

cv::Mat DecodePng(std::span<const std::uint8_t> bytes) {
  png_image image;
  std::memset(&image, 0, sizeof(image));
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size())) {
    throw InvalidInputError(std::string("the PNG does not decode: ") + image.message);
  }
  if (image.width == 0 || image.height == 0 || image.width > kMaxImageSide || image.height > kMaxImageSide ||
      std::uint64_t{image.width} * image.height > kMaxImagePixels) {
    png_image_free(&image);
    throw InvalidInputError("the PNG's size " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                            " is out of range");
  }
  image.format = PNG_FORMAT_BGRA;
  image.flags |= PNG_IMAGE_FLAG_16BIT_sRGB;  // 16-bit values without gAMA or sRGB: sRGB, not linear
  cv::Mat bgra(static_cast<int>(image.height), static_cast<int>(image.width), CV_8UC4);
  if (!png_image_finish_read(&image, nullptr, bgra.data, static_cast<png_int_32>(bgra.step[0]), nullptr)) {
    throw InvalidInputError(std::string("the PNG does not decode: ") + image.message);
  }
  return bgra;
}

namespace {

struct PngWriteState {
  std::vector<std::uint8_t>* out;
  std::jmp_buf jump;
  char message[256];
};

void OnPngError(png_structp png, png_const_charp message) {
  auto* state = static_cast<PngWriteState*>(png_get_error_ptr(png));
  std::snprintf(state->message, sizeof(state->message), "%s", message);
  std::longjmp(state->jump, 1);
}
void OnPngWarning(png_structp, png_const_charp) {}
void OnPngWrite(png_structp png, png_bytep data, png_size_t size) {
  auto* state = static_cast<PngWriteState*>(png_get_io_ptr(png));
  state->out->insert(state->out->end(), data, data + size);  // cannot throw past libpng: reserved below
}
void OnPngFlush(png_structp) {}

// Only trivially destructible locals here: libpng's errors longjmp back to the setjmp.
bool WriteRows(PngWriteState& state, const cv::Mat& image, std::optional<int> compression) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, OnPngError, OnPngWarning);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(state.jump)) {
    png_destroy_write_struct(&png, info ? &info : nullptr);
    return false;
  }
  png_set_write_fn(png, &state, OnPngWrite, OnPngFlush);
  if (compression) {
    png_set_compression_level(png, *compression);
  } else {
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_set_compression_level(png, Z_BEST_SPEED);
    png_set_compression_strategy(png, Z_RLE);
  }
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows), 8,
               image.channels() == 4 ? PNG_COLOR_TYPE_RGBA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_set_bgr(png);
  for (int y = 0; y < image.rows; ++y) png_write_row(png, image.ptr<png_byte>(y));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

}  // namespace facerig::codec

namespace facerig {

std::vector<std::uint8_t> EncodePngBytes(const cv::Mat& image, std::optional<int> compression) {
  if (image.depth() != CV_8U || (image.channels() != 3 && image.channels() != 4) || image.empty()) {
    throw InvalidInputError("PNG encoding takes an 8-bit BGR or BGRA image");
  }
  if (compression && (*compression < 0 || *compression > 9)) throw InvalidInputError("PNG compression out of [0, 9]");
  std::vector<std::uint8_t> bytes;
  // The worst case of zlib's stored blocks: the write callback never has to grow the vector.
  const std::size_t raw = (image.total() * image.elemSize() + static_cast<std::size_t>(image.rows)) * 102 / 100;
  bytes.reserve(raw + 4096);
  codec::PngWriteState state{.out = &bytes, .jump = {}, .message = {}};
  if (!codec::WriteRows(state, image, compression)) {
    throw InvalidInputError(std::string("PNG encoding failed: ") + state.message);
  }
  return bytes;
}

}  // namespace facerig
