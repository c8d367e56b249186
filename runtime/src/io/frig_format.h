// The .frig v1 layout (frig.h documents it) shared by the reader and the
// writer: sizes, field offsets and the section kinds. Private to facerig::runtime.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "facerig/runtime/rig.h"

namespace facerig::frig_format {

inline constexpr std::uint64_t kHeaderSize = 32;
inline constexpr std::uint64_t kTableEntrySize = 32;
inline constexpr std::uint64_t kSectionAlignment = 16;
inline constexpr std::uint64_t kMetaSize = 32;
inline constexpr std::uint32_t kFlagHasUvs = 1u << 0;
inline constexpr std::uint32_t kFlagHasNormalDeltas = 1u << 1;
inline constexpr std::uint32_t kKnownFlags = kFlagHasUvs | kFlagHasNormalDeltas;
inline constexpr std::uint32_t kMaxUnits = static_cast<std::uint32_t>(Units::kMetres);
inline constexpr std::uint32_t kMaxUpAxis = static_cast<std::uint32_t>(UpAxis::kZ);

// Header field offsets.
inline constexpr std::uint64_t kMagicAt = 0;
inline constexpr std::uint64_t kVersionAt = 4;
inline constexpr std::uint64_t kSectionCountAt = 8;
inline constexpr std::uint64_t kCrcAt = 12;
inline constexpr std::uint64_t kFileSizeAt = 16;
// Bytes 24..31 are reserved: written as 0 and ignored, room for later use.

// Section table entry field offsets.
inline constexpr std::uint64_t kEntryTagAt = 0;
inline constexpr std::uint64_t kEntryElementSizeAt = 4;
inline constexpr std::uint64_t kEntryCountAt = 8;
inline constexpr std::uint64_t kEntryOffsetAt = 16;
inline constexpr std::uint64_t kEntryByteSizeAt = 24;

// The FourCC as the little-endian u32 of its four characters, so that the
// file holds the characters in reading order.
constexpr std::uint32_t MakeTag(const char (&name)[5]) {
  return static_cast<std::uint32_t>(static_cast<unsigned char>(name[0])) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(name[1])) << 8 |
         static_cast<std::uint32_t>(static_cast<unsigned char>(name[2])) << 16 |
         static_cast<std::uint32_t>(static_cast<unsigned char>(name[3])) << 24;
}

enum Section : std::size_t {
  kMeta,
  kPositions,
  kNormals,
  kTriangles,
  kUvs,
  kParts,
  kShapes,
  kShapeIndices,
  kShapePositions,
  kShapeNormals,
  kStrings,
  kSectionKindCount,
};

struct SectionKind {
  std::uint32_t tag;
  std::uint32_t element_size;
  bool required;
};

// In file order.
inline constexpr std::array<SectionKind, kSectionKindCount> kSectionKinds = {{
    {MakeTag("META"), static_cast<std::uint32_t>(kMetaSize), true},
    {MakeTag("POSI"), 12, true},
    {MakeTag("NORM"), 12, true},
    {MakeTag("TRIS"), 12, true},
    {MakeTag("UV00"), 8, false},
    {MakeTag("PART"), 16, true},
    {MakeTag("SHAP"), 16, true},
    {MakeTag("SIDX"), 4, true},
    {MakeTag("SPOS"), 12, true},
    {MakeTag("SNRM"), 12, false},
    {MakeTag("STRS"), 1, true},
}};

}  // namespace facerig::frig_format
