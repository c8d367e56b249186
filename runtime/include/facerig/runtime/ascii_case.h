// Case-insensitive matching of ASCII names: file extensions, units, part,
// shape and voice names. Not locale-aware on purpose: these are identifiers.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace facerig {

// A-Z lowered, every other byte as it is.
std::string LowerAscii(std::string_view text);

bool EqualIgnoringAsciiCase(std::string_view a, std::string_view b);

// The path's extension with its dot, lowered: "head.GLB" -> ".glb"; "" when none.
std::string LowerExtension(const std::filesystem::path& path);

}  // namespace facerig
