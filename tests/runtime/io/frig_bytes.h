// Reading and editing .frig bytes in tests: little-endian fields, the section
// table, and the checksum fixed after an edit so that the check under test is
// reached.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/io/frig.h"

namespace facerig::test {

using Bytes = std::vector<std::byte>;

inline std::uint32_t Get32(const Bytes& bytes, std::uint64_t at) {
  std::uint32_t value = 0;
  for (int i = 3; i >= 0; --i) value = value << 8 | std::to_integer<std::uint32_t>(bytes[at + i]);
  return value;
}
inline std::uint64_t Get64(const Bytes& bytes, std::uint64_t at) {
  return Get32(bytes, at) | std::uint64_t{Get32(bytes, at + 4)} << 32;
}
inline void Put32(Bytes& bytes, std::uint64_t at, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) bytes[at + i] = static_cast<std::byte>((value >> (8 * i)) & 0xFFu);
}
inline void Put64(Bytes& bytes, std::uint64_t at, std::uint64_t value) {
  Put32(bytes, at, static_cast<std::uint32_t>(value & 0xFFFFFFFFu));
  Put32(bytes, at + 4, static_cast<std::uint32_t>(value >> 32));
}
inline void PutFloat(Bytes& bytes, std::uint64_t at, float value) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &value, sizeof(bits));
  Put32(bytes, at, bits);
}
// Makes an edited file pass the checksum, so the check under test is reached.
inline void FixCrc(Bytes& bytes) { Put32(bytes, 12, Crc32(std::span(bytes).subspan(32))); }

struct SectionInfo {
  std::uint64_t entry;  // offset of its section table entry
  std::uint64_t count;
  std::uint64_t offset;
};

inline std::optional<SectionInfo> FindSection(const Bytes& bytes, std::string_view tag) {
  const std::uint32_t count = Get32(bytes, 8);
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::uint64_t entry = 32 + 32 * std::uint64_t{i};
    if (std::memcmp(&bytes[entry], tag.data(), 4) == 0) {
      return SectionInfo{entry, Get64(bytes, entry + 8), Get64(bytes, entry + 16)};
    }
  }
  return std::nullopt;
}
inline SectionInfo Section(const Bytes& bytes, std::string_view tag) {
  const std::optional<SectionInfo> info = FindSection(bytes, tag);
  REQUIRE(info);
  return *info;
}

// Parses bytes that must be refused and returns the error, checking that it names the path.
inline IoError ParseError(const Bytes& bytes, const std::string& path = "corpus/bad.frig") {
  try {
    static_cast<void>(ParseFrig(bytes, path));
  } catch (const IoError& error) {
    CHECK_THAT(error.what(), Catch::Matchers::Contains(path));
    return error;
  }
  FAIL("ParseFrig accepted malformed bytes");
  throw std::logic_error("unreachable");
}

}  // namespace facerig::test
