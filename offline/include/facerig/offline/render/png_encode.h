// PNG encoding of 8-bit images (OpenCV imgcodecs): the textures the library
// paints and bakes, and the frames and screenshots the player writes.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "facerig/runtime/material.h"

namespace facerig {

// `pixels`: `width` x `height` texels of `channels` bytes each (3: RGB,
// 4: RGBA), rows top to bottom; the PNG keeps the channels. `compression`:
// the zlib level 0-9, none for OpenCV's default. `name` becomes the image's
// name. Throws InvalidInputError naming `name` when the sizes disagree or
// encoding fails.
EncodedImage EncodePng(std::span<const std::uint8_t> pixels, int width, int height, int channels,
                       std::string name, std::optional<int> compression = std::nullopt);

}  // namespace facerig
