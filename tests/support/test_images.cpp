#include "test_images.h"

#include <array>
#include <string>

namespace facerig::test {
namespace {

std::uint32_t Crc32(const std::uint8_t* data, std::size_t size) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) {
    crc ^= data[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

void PutBigEndian(std::vector<std::uint8_t>* out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8) out->push_back(static_cast<std::uint8_t>(value >> shift));
}

void PutChunk(std::vector<std::uint8_t>* out, const char* type, const std::vector<std::uint8_t>& data) {
  PutBigEndian(out, static_cast<std::uint32_t>(data.size()));
  std::vector<std::uint8_t> typed(type, type + 4);
  typed.insert(typed.end(), data.begin(), data.end());
  out->insert(out->end(), typed.begin(), typed.end());
  PutBigEndian(out, Crc32(typed.data(), typed.size()));
}

// zlib stream of stored blocks (at most 65535 bytes each) with its Adler-32.
std::vector<std::uint8_t> StoredZlib(const std::vector<std::uint8_t>& raw) {
  std::vector<std::uint8_t> out = {0x78, 0x01};
  std::size_t at = 0;
  do {
    const std::size_t size = std::min<std::size_t>(raw.size() - at, 65535);
    out.push_back(at + size == raw.size() ? 1 : 0);
    out.push_back(static_cast<std::uint8_t>(size));
    out.push_back(static_cast<std::uint8_t>(size >> 8));
    out.push_back(static_cast<std::uint8_t>(~size));
    out.push_back(static_cast<std::uint8_t>(~size >> 8));
    out.insert(out.end(), raw.begin() + static_cast<std::ptrdiff_t>(at), raw.begin() + static_cast<std::ptrdiff_t>(at + size));
    at += size;
  } while (at < raw.size());
  std::uint32_t a = 1, b = 0;
  for (std::uint8_t byte : raw) {
    a = (a + byte) % 65521;
    b = (b + a) % 65521;
  }
  PutBigEndian(&out, (b << 16) | a);
  return out;
}

}  // namespace

std::vector<std::uint8_t> EncodePng(std::uint32_t width, std::uint32_t height, const std::vector<glm::u8vec4>& pixels) {
  std::vector<std::uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  std::vector<std::uint8_t> header;
  PutBigEndian(&header, width);
  PutBigEndian(&header, height);
  header.insert(header.end(), {8, 6, 0, 0, 0});  // 8-bit RGBA, deflate, no filter method, no interlace
  PutChunk(&out, "IHDR", header);
  std::vector<std::uint8_t> rows;
  for (std::uint32_t y = 0; y < height; ++y) {
    rows.push_back(0);  // filter: none
    for (std::uint32_t x = 0; x < width; ++x) {
      const glm::u8vec4& p = pixels[std::size_t{y} * width + x];
      rows.insert(rows.end(), {p.r, p.g, p.b, p.a});
    }
  }
  PutChunk(&out, "IDAT", StoredZlib(rows));
  PutChunk(&out, "IEND", {});
  return out;
}

std::vector<std::uint8_t> CheckerPng(std::uint32_t size, std::uint32_t cells, glm::u8vec4 a, glm::u8vec4 b) {
  std::vector<glm::u8vec4> pixels(std::size_t{size} * size);
  for (std::uint32_t y = 0; y < size; ++y) {
    for (std::uint32_t x = 0; x < size; ++x) {
      const bool odd = ((x * cells / size) + (y * cells / size)) % 2 == 1;
      pixels[std::size_t{y} * size + x] = odd ? b : a;
    }
  }
  return EncodePng(size, size, pixels);
}

EncodedImage CheckerImage(const char* name, std::uint32_t size, std::uint32_t cells, glm::u8vec4 a, glm::u8vec4 b) {
  return EncodedImage{.name = name, .format = ImageFormat::kPng, .width = size, .height = size,
                      .bytes = CheckerPng(size, cells, a, b)};
}

}  // namespace facerig::test
