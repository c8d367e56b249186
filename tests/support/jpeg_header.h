// The first bytes of a baseline JPEG, written by hand: enough for ProbeImage
// (which reads headers only), no pixels to decode.
#pragma once

#include <cstdint>
#include <vector>

namespace facerig::test {

// SOI, a JFIF APP0 segment, a baseline frame header (SOF0) of `width` x
// `height` with 3 components, then EOI.
inline std::vector<std::uint8_t> JpegHeader(std::uint16_t width, std::uint16_t height) {
  std::vector<std::uint8_t> bytes = {0xFF, 0xD8,                                                  // SOI
                                     0xFF, 0xE0, 0x00, 0x10, 'J', 'F', 'I', 'F', 0x00, 0x01, 0x01,  // APP0
                                     0x00, 0x00, 0x01, 0x00, 0x01, 0x00, 0x00,
                                     0xFF, 0xC0, 0x00, 0x11, 0x08,  // SOF0, length 17, 8-bit
                                     0x00, 0x00, 0x00, 0x00,        // height, width: below
                                     0x03, 0x01, 0x22, 0x00, 0x02, 0x11, 0x01, 0x03, 0x11, 0x01,
                                     0xFF, 0xD9};  // EOI
  bytes[25] = static_cast<std::uint8_t>(height >> 8);
  bytes[26] = static_cast<std::uint8_t>(height & 0xFF);
  bytes[27] = static_cast<std::uint8_t>(width >> 8);
  bytes[28] = static_cast<std::uint8_t>(width & 0xFF);
  return bytes;
}

}  // namespace facerig::test
