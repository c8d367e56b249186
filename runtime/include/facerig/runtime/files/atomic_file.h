// Writing files so that a failure never leaves a half-written output: data
// goes to a temporary file beside the target, which is renamed over it only
// once complete.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace facerig {

// Writes `bytes` to `path` atomically. Throws IoError(kWriteFailed) naming the path.
void WriteFileAtomically(const std::filesystem::path& path, std::span<const std::byte> bytes);
void WriteFileAtomically(const std::filesystem::path& path, std::string_view text);

// Reads a whole file: ReadInputFile / ReadInputText (input_file.h), which
// refuse anything but a regular file and check `max_bytes` before allocating.
std::vector<std::byte> ReadFileBytes(const std::filesystem::path& path,
                                     std::uint64_t max_bytes = std::uint64_t{4} << 30);
std::string ReadFileText(const std::filesystem::path& path,
                         std::uint64_t max_bytes = std::uint64_t{4} << 30);

}  // namespace facerig
