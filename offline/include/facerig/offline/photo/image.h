// A photograph read for fitting a face to it: a PNG or JPEG of any size the
// project's image reader accepts (image_file.h checks the header and caps the
// size before anything is decoded), decoded to 8-bit RGB (grey-scale, palette,
// 16-bit and alpha images converted; a JPEG's EXIF orientation applied) and
// brought down to at most `max_side` pixels on its longer side.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "facerig/offline/render/rasterizer.h"
#include "facerig/runtime/files/image_file.h"

namespace facerig {

struct PhotoReadParams {
  // dlib's detector takes time in proportion to the pixels, and 2048 px
  // already shows a portrait's face at several times the baked texture's
  // 1024 texels; larger photos add time, not detail.
  int max_side = 2048;
  // Images with more pixels than this are refused before decoding (the
  // header says the size): image_file.h's cap, or less where memory is short.
  std::uint64_t max_pixels = kMaxImagePixels;
};

struct Photo {
  RgbImage image;  // what the fit sees: at most max_side pixels a side
  int original_width = 0, original_height = 0;
  float scale = 1.0f;  // image pixels per original pixel (1, or less when downscaled)
  bool grey = false;   // every pixel has R == G == B (the baked skin will be grey)
  // What the reader changed or noticed, one sentence each, e.g.
  // "downscaled from 4000x3000 to 2048x1536".
  std::vector<std::string> notes;
};

// \throw IoError naming the file: kOpenFailed when it cannot be read; as
//        ProbeImage (kBadMagic for a file that is neither PNG nor JPEG,
//        kTruncated, kAbsurdCount for a size over its caps or max_pixels);
//        kParse when the image data does not decode.
// \throw InvalidInputError when max_side < 16.
Photo ReadPhoto(const std::filesystem::path& path, const PhotoReadParams& params = {});

// The same for a photo already in memory; `name` stands for the file in errors.
Photo DecodePhoto(std::span<const std::byte> bytes, const std::string& name, const PhotoReadParams& params = {});

}  // namespace facerig
