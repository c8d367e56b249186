// The .frig v1 layout (frig.h documents it) shared by the reader and the
// writer: sizes, field offsets, the section kinds and little-endian packing. Private to facerig::runtime.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <utility>

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
inline constexpr std::uint64_t kMaterialSize = 48;
inline constexpr std::uint64_t kImageEntrySize = 32;
inline constexpr std::uint64_t kImageAlignment = 8;  // within 'IMGB', itself 16-aligned
inline constexpr std::uint32_t kMaterialDoubleSided = 1u << 0;
inline constexpr std::uint32_t kKnownMaterialFlags = kMaterialDoubleSided;
inline constexpr std::uint32_t kMaxAlphaMode = static_cast<std::uint32_t>(AlphaMode::kBlend);
inline constexpr std::uint32_t kMaxImageFormat = static_cast<std::uint32_t>(ImageFormat::kJpeg);

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
  kMaterials,
  kPartMaterials,
  kImages,
  kImageBytes,
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
    {MakeTag("MATL"), static_cast<std::uint32_t>(kMaterialSize), false},
    {MakeTag("PMAT"), 4, false},
    {MakeTag("IMGS"), static_cast<std::uint32_t>(kImageEntrySize), false},
    {MakeTag("IMGB"), 1, false},
}};

// Where a known section is, as the reader found it in the section table.
struct SectionRef {
  bool present = false;
  std::uint64_t table_entry = 0;  // file offset of its section table entry
  std::uint64_t count = 0;
  std::uint64_t offset = 0;
};
using SectionRefs = std::array<SectionRef, kSectionKindCount>;

// A name in 'STRS': (offset, length).
using NameRef = std::pair<std::uint32_t, std::uint32_t>;

constexpr std::uint64_t AlignUp(std::uint64_t value, std::uint64_t alignment) {
  return (value + alignment - 1) / alignment * alignment;
}

// Explicit little-endian packing, independent of the host's byte order.
inline std::uint32_t Load32(const std::byte* p) {
  return std::to_integer<std::uint32_t>(p[0]) | std::to_integer<std::uint32_t>(p[1]) << 8 |
         std::to_integer<std::uint32_t>(p[2]) << 16 | std::to_integer<std::uint32_t>(p[3]) << 24;
}
inline std::uint64_t Load64(const std::byte* p) {
  return static_cast<std::uint64_t>(Load32(p)) | static_cast<std::uint64_t>(Load32(p + 4)) << 32;
}
// std::bit_cast, or the compiler builtin it is made of where the standard
// library lacks it (libc++ 13 of Debian's emscripten).
template <class To, class From>
constexpr To BitCast(const From& from) noexcept {
#if defined(__cpp_lib_bit_cast)
  return std::bit_cast<To>(from);
#else
  return __builtin_bit_cast(To, from);
#endif
}

inline float LoadFloat(const std::byte* p) { return BitCast<float>(Load32(p)); }
inline void Store32(std::byte* p, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::byte>((value >> (8 * i)) & 0xFFu);
}
inline void Store64(std::byte* p, std::uint64_t value) {
  Store32(p, static_cast<std::uint32_t>(value & 0xFFFFFFFFu));
  Store32(p + 4, static_cast<std::uint32_t>(value >> 32));
}

// Writes consecutive fields into a buffer sized beforehand.
class Cursor {
 public:
  explicit Cursor(std::byte* p) : p_(p) {}
  void U32(std::uint32_t value) {
    Store32(p_, value);
    p_ += 4;
  }
  void U64(std::uint64_t value) {
    Store64(p_, value);
    p_ += 8;
  }
  void Float(float value) { U32(BitCast<std::uint32_t>(value)); }
  void Vec2(const glm::vec2& v) {
    Float(v.x);
    Float(v.y);
  }
  void Vec3(const glm::vec3& v) {
    Float(v.x);
    Float(v.y);
    Float(v.z);
  }
  void Bytes(std::string_view text) {
    for (char c : text) *p_++ = static_cast<std::byte>(c);
  }

 private:
  std::byte* p_;
};

}  // namespace facerig::frig_format
