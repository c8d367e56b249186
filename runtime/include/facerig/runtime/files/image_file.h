// Image files (PNG and JPEG) as materials use them: read as they are, never
// decoded here; the header is checked so that a renderer can trust the size
// before it allocates pixels.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "facerig/runtime/material.h"

namespace facerig {

// Caps for an image a face needs (a 16k texture is four times what any asset
// in the project uses): bytes of the file, pixels per side, and pixels in all.
inline constexpr std::uint64_t kMaxImageFileBytes = std::uint64_t{256} << 20;
inline constexpr std::uint32_t kMaxImageSide = 16384;
inline constexpr std::uint64_t kMaxImagePixels = std::uint64_t{1} << 27;

struct ImageHeader {
  ImageFormat format = ImageFormat::kPng;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
};

// The format and size from a PNG's IHDR or a JPEG's first frame header.
// Throws IoError naming `path_for_errors`: kBadMagic for neither format,
// kTruncated when the header ends early, kAbsurdCount for a size of zero or
// over the caps above.
ImageHeader ProbeImage(std::span<const std::byte> bytes, const std::string& path_for_errors);

// `bytes` probed and kept as an image called `name` (a plain file name).
EncodedImage MakeEncodedImage(std::span<const std::byte> bytes, std::string name,
                              const std::string& path_for_errors);

// A regular file read through ReadInputFile (at most kMaxImageFileBytes) and
// probed; its name is the file name. The caller confines the path
// (ResolveInsideFolder) when another file named it.
EncodedImage ReadImageFile(const std::filesystem::path& path);

}  // namespace facerig
