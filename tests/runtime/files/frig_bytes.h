// Reading and editing .frig bytes in tests: little-endian fields, the section
// table, and the checksum fixed after an edit so that the check under test is
// reached (`using namespace facerig::test::frig_bytes;`).
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
#include "facerig/runtime/files/frig.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig::test::frig_bytes {

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

// What a sweep of bit flips found: the files refused (IoError), those
// accepted, and the first accepted rig that does not validate ("byte N: why").
struct FlipSweep {
  std::size_t refused = 0;
  std::size_t accepted = 0;
  std::string first_invalid;
};

// Flips the lowest bit (off-by-one counts and indices) and then the highest
// (huge values, the sign of floats) of every byte from `first` on, one flip at
// a time, and parses the result. The checksum is recomputed after each flip so
// that every structural check is reached; a flip in the checksum field itself
// stays a mismatch. No Catch macros inside: under ASan they would dominate.
inline FlipSweep FlipEveryByte(const Bytes& reference, std::uint64_t first) {
  FlipSweep sweep;
  Bytes bytes = reference;
  for (std::uint64_t at = first; at < reference.size(); ++at) {
    for (const std::byte mask : {std::byte{0x01}, std::byte{0x80}}) {
      bytes[at] ^= mask;
      if (at < 12 || at >= 16) FixCrc(bytes);
      try {
        const Rig rig = ParseFrig(bytes, "flipped.frig");
        std::string problem;
        if (!RigBuilder::ToRaw(rig).Validate(&problem) && sweep.first_invalid.empty()) {
          sweep.first_invalid = "byte " + std::to_string(at) + ": " + problem;
        }
        ++sweep.accepted;
      } catch (const IoError&) {
        ++sweep.refused;
      }
      bytes[at] = reference[at];
      std::memcpy(&bytes[12], &reference[12], 4);  // the checksum field
    }
  }
  return sweep;
}

}  // namespace facerig::test::frig_bytes
