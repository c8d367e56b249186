// Reading input files that may be hostile: only regular files are opened, sizes
// are checked before anything is allocated, paths named inside a file stay in
// that file's folder, JSON nesting is bounded, and text quoted from the input
// in an error message is short.
//
// Every reader in facerig (OBJ, glTF/GLB, .frig, phoneme tracks, mapping
// files) opens its file through ReadInputFile, and glTF buffer and image URIs
// go through ResolveInsideFolder.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace facerig {

// The largest input file any reader accepts unless it states a smaller cap:
// 4 GiB, beyond what the 32-bit counts of GLB and .frig can describe.
inline constexpr std::uint64_t kMaxInputFileBytes = std::uint64_t{4} << 30;

// The deepest JSON nesting (objects and arrays) a reader accepts. glTF files
// and facerig's own JSON need fewer than 16 levels; tinygltf's recursive
// parser overflows the stack near 15,000.
inline constexpr int kMaxJsonNesting = 64;

// How many bytes of input an error message quotes at most.
inline constexpr std::size_t kMaxQuotedInputBytes = 200;

// Reads a whole regular file. A FIFO, socket, device or directory is refused
// (IoError kOpenFailed) without blocking; a file larger than `max_bytes` is
// refused (kAbsurdCount) before its bytes are allocated; a missing or
// unreadable file is kOpenFailed; a file that shrinks while read is kTruncated.
std::vector<std::byte> ReadInputFile(const std::filesystem::path& path,
                                     std::uint64_t max_bytes = kMaxInputFileBytes);
std::string ReadInputText(const std::filesystem::path& path, std::uint64_t max_bytes = kMaxInputFileBytes);

// Resolves `reference`, a path named by `field` of `file` (e.g. a glTF
// buffer's uri, already percent-decoded), against `file`'s folder. Throws
// IoError(kOpenFailed) naming `file` and `field` when `reference` is empty or
// absolute, contains a NUL byte, or leads outside that folder through `..` or a
// symbolic link. The result is canonical; it need not exist.
std::filesystem::path ResolveInsideFolder(const std::filesystem::path& file, std::string_view reference,
                                          std::string_view field);

// Whether `path` lies inside `folder` (lexically: neither is resolved, so
// both must be in the same form, e.g. both normalised).
bool IsInsideFolder(const std::filesystem::path& path, const std::filesystem::path& folder);

// Throws IoError(kParse) naming `path` (with the byte offset) when the JSON
// `text` nests objects and arrays deeper than `max_depth`. Brackets inside
// strings do not count; the text need not be valid JSON.
void CheckJsonNesting(std::string_view text, const std::string& path, int max_depth = kMaxJsonNesting);

// `text` for an error message: at most `max_bytes` of it followed by "..."
// when cut, control and non-ASCII bytes shown as '?'.
std::string QuoteInput(std::string_view text, std::size_t max_bytes = kMaxQuotedInputBytes);

}  // namespace facerig
