// Small images for tests, encoded without any image library: PNGs with stored
// (uncompressed) deflate blocks, so runtime tests need no OpenCV.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include "facerig/runtime/material.h"

namespace facerig::test {

// An 8-bit RGBA PNG; `pixels` holds width * height colours, row 0 at the top.
std::vector<std::uint8_t> EncodePng(std::uint32_t width, std::uint32_t height,
                                    const std::vector<glm::u8vec4>& pixels);
// A `cells` x `cells` checker of `a` and `b` (`a` at the top-left), `size` pixels square.
std::vector<std::uint8_t> CheckerPng(std::uint32_t size, std::uint32_t cells, glm::u8vec4 a, glm::u8vec4 b);
// The same as an EncodedImage called `name`.
EncodedImage CheckerImage(const char* name, std::uint32_t size, std::uint32_t cells, glm::u8vec4 a, glm::u8vec4 b);

}  // namespace facerig::test
