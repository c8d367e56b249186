// Shared by the libFuzzer entry points: the readers must return or throw
// IoError for any input; any other exception, a crash or a sanitizer report
// is a finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace facerig::fuzz {

inline std::span<const std::byte> Bytes(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const std::byte*>(data), size};
}
inline std::string_view Text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Inputs are named as files in a folder that does not exist, so that an
// external URI finds nothing to read, whatever it names.
inline constexpr const char* kFolder = "/nonexistent-facerig-fuzz/";

}  // namespace facerig::fuzz
