// JPEG through libjpeg-turbo: its errors longjmp, so each pass over the file
// is a function whose locals need no destructor; the header pass sizes the
// image and finds the EXIF orientation, the second decodes into it.
#include "io/image_codec_internal.h"

#include <csetjmp>
#include <cstdio>
#include <string>

#include <jpeglib.h>

#include "facerig/offline/error.h"
#include "facerig/runtime/files/image_file.h"

namespace facerig::codec {
namespace {

struct JpegErrors {
  jpeg_error_mgr manager;  // first: libjpeg sees this struct as its jpeg_error_mgr
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void OnJpegError(j_common_ptr info) {
  auto* errors = reinterpret_cast<JpegErrors*>(info->err);
  (*info->err->format_message)(info, errors->message);
  std::longjmp(errors->jump, 1);
}
void OnJpegMessage(j_common_ptr, int) {}  // corrupt-data warnings: the decoder goes on, as OpenCV's did

struct JpegHeader {
  int width = 0, height = 0;
  bool cmyk = false;
  int orientation = 1;
};

void StartDecompress(jpeg_decompress_struct& info, JpegErrors& errors, std::span<const std::uint8_t> bytes) {
  info.err = jpeg_std_error(&errors.manager);
  errors.manager.error_exit = OnJpegError;
  errors.manager.emit_message = OnJpegMessage;
  jpeg_create_decompress(&info);
  jpeg_mem_src(&info, bytes.data(), static_cast<unsigned long>(bytes.size()));
}

bool ReadHeader(std::span<const std::uint8_t> bytes, JpegHeader& header, JpegErrors& errors) {
  jpeg_decompress_struct info;
  if (setjmp(errors.jump)) {
    jpeg_destroy_decompress(&info);
    return false;
  }
  StartDecompress(info, errors, bytes);
  jpeg_save_markers(&info, JPEG_APP0 + 1, 0xFFFF);
  jpeg_read_header(&info, TRUE);
  header.width = static_cast<int>(info.image_width);
  header.height = static_cast<int>(info.image_height);
  header.cmyk = info.jpeg_color_space == JCS_CMYK || info.jpeg_color_space == JCS_YCCK;
  for (jpeg_saved_marker_ptr marker = info.marker_list; marker; marker = marker->next) {
    if (marker->marker == JPEG_APP0 + 1) {
      const int orientation = ExifOrientation(std::span<const std::uint8_t>(marker->data, marker->data_length));
      if (orientation) header.orientation = orientation;
    }
  }
  jpeg_destroy_decompress(&info);
  return true;
}

bool DecodeInto(std::span<const std::uint8_t> bytes, std::uint8_t* bgr, std::size_t stride, JpegErrors& errors) {
  jpeg_decompress_struct info;
  if (setjmp(errors.jump)) {
    jpeg_destroy_decompress(&info);
    return false;
  }
  StartDecompress(info, errors, bytes);
  jpeg_read_header(&info, TRUE);
  info.out_color_space = JCS_EXT_BGR;  // libjpeg-turbo converts grey and YCbCr to BGR
  jpeg_start_decompress(&info);
  while (info.output_scanline < info.output_height) {
    JSAMPROW row = bgr + stride * info.output_scanline;
    jpeg_read_scanlines(&info, &row, 1);
  }
  jpeg_finish_decompress(&info);
  jpeg_destroy_decompress(&info);
  return true;
}

}  // namespace

cv::Mat DecodeJpeg(std::span<const std::uint8_t> bytes) {
  JpegErrors errors{};
  JpegHeader header;
  if (!ReadHeader(bytes, header, errors)) {
    throw InvalidInputError(std::string("the JPEG does not decode: ") + errors.message);
  }
  if (header.cmyk) throw InvalidInputError("the JPEG is CMYK: save it as RGB");
  if (header.width <= 0 || header.height <= 0 || header.width > static_cast<int>(kMaxImageSide) ||
      header.height > static_cast<int>(kMaxImageSide) ||
      std::uint64_t(header.width) * std::uint64_t(header.height) > kMaxImagePixels) {
    throw InvalidInputError("the JPEG's size " + std::to_string(header.width) + "x" + std::to_string(header.height) +
                            " is out of range");
  }
  cv::Mat bgr(header.height, header.width, CV_8UC3);
  if (!DecodeInto(bytes, bgr.data, bgr.step[0], errors)) {
    throw InvalidInputError(std::string("the JPEG does not decode: ") + errors.message);
  }
  return Oriented(bgr, header.orientation);
}

}  // namespace facerig::codec
