#include "facerig/runtime/io/frig.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string_view>
#include <utility>

#include "facerig/runtime/error.h"
#include "facerig/runtime/io/atomic_file.h"
#include "facerig/runtime/io/input_file.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {
namespace {

constexpr std::uint64_t kHeaderSize = 32;
constexpr std::uint64_t kTableEntrySize = 32;
constexpr std::uint64_t kSectionAlignment = 16;
constexpr std::uint64_t kMetaSize = 32;
constexpr std::uint32_t kFlagHasUvs = 1u << 0;
constexpr std::uint32_t kFlagHasNormalDeltas = 1u << 1;
constexpr std::uint32_t kKnownFlags = kFlagHasUvs | kFlagHasNormalDeltas;
constexpr std::uint32_t kMaxUnits = static_cast<std::uint32_t>(Units::kMetres);
constexpr std::uint32_t kMaxUpAxis = static_cast<std::uint32_t>(UpAxis::kZ);

// Header field offsets.
constexpr std::uint64_t kMagicAt = 0;
constexpr std::uint64_t kVersionAt = 4;
constexpr std::uint64_t kSectionCountAt = 8;
constexpr std::uint64_t kCrcAt = 12;
constexpr std::uint64_t kFileSizeAt = 16;
// Bytes 24..31 are reserved: written as 0 and ignored, room for later use.

// Section table entry field offsets.
constexpr std::uint64_t kEntryTagAt = 0;
constexpr std::uint64_t kEntryElementSizeAt = 4;
constexpr std::uint64_t kEntryCountAt = 8;
constexpr std::uint64_t kEntryOffsetAt = 16;
constexpr std::uint64_t kEntryByteSizeAt = 24;

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
constexpr std::array<SectionKind, kSectionKindCount> kSectionKinds = {{
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

std::optional<Section> FindSectionKind(std::uint32_t tag) {
  for (std::size_t i = 0; i < kSectionKinds.size(); ++i) {
    if (kSectionKinds[i].tag == tag) return static_cast<Section>(i);
  }
  return std::nullopt;
}

// A tag for messages; unprintable bytes become '?'.
std::string TagName(std::uint32_t tag) {
  std::string name(4, '?');
  for (int i = 0; i < 4; ++i) {
    const auto c = static_cast<char>((tag >> (8 * i)) & 0xFFu);
    if (c >= 0x20 && c < 0x7F) name[static_cast<std::size_t>(i)] = c;
  }
  return "'" + name + "'";
}

std::string Hex32(std::uint32_t value) {
  char text[16];
  std::snprintf(text, sizeof(text), "0x%08X", static_cast<unsigned>(value));
  return text;
}

constexpr std::uint64_t AlignUp(std::uint64_t value) {
  return (value + kSectionAlignment - 1) / kSectionAlignment * kSectionAlignment;
}

// Explicit little-endian packing, independent of the host's byte order.
std::uint32_t Load32(const std::byte* p) {
  return std::to_integer<std::uint32_t>(p[0]) | std::to_integer<std::uint32_t>(p[1]) << 8 |
         std::to_integer<std::uint32_t>(p[2]) << 16 | std::to_integer<std::uint32_t>(p[3]) << 24;
}
std::uint64_t Load64(const std::byte* p) {
  return static_cast<std::uint64_t>(Load32(p)) | static_cast<std::uint64_t>(Load32(p + 4)) << 32;
}
float LoadFloat(const std::byte* p) { return std::bit_cast<float>(Load32(p)); }

void Store32(std::byte* p, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::byte>((value >> (8 * i)) & 0xFFu);
}
void Store64(std::byte* p, std::uint64_t value) {
  Store32(p, static_cast<std::uint32_t>(value & 0xFFFFFFFFu));
  Store32(p + 4, static_cast<std::uint32_t>(value >> 32));
}

// Slicing-by-8 tables: table[0] is the classic byte-at-a-time table, table[k]
// advances a byte through k more zero bytes, so 8 bytes go per step.
using CrcTables = std::array<std::array<std::uint32_t, 256>, 8>;
constexpr CrcTables MakeCrcTables() {
  CrcTables tables{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    tables[0][i] = c;
  }
  for (std::size_t k = 1; k < tables.size(); ++k) {
    for (std::size_t i = 0; i < 256; ++i) {
      const std::uint32_t previous = tables[k - 1][i];
      tables[k][i] = (previous >> 8) ^ tables[0][previous & 0xFFu];
    }
  }
  return tables;
}
constexpr CrcTables kCrcTables = MakeCrcTables();

// ---------------------------------------------------------------- writing --

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
  void Float(float value) { U32(std::bit_cast<std::uint32_t>(value)); }
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

std::uint32_t CheckedU32(std::uint64_t value, const char* what, const std::string& path) {
  if (value > std::numeric_limits<std::uint32_t>::max()) {
    throw IoError(IoErrorKind::kInvalidRig, path,
                  std::string(what) + " " + std::to_string(value) + " does not fit in .frig v1");
  }
  return static_cast<std::uint32_t>(value);
}

// The string table: part names, then shape names, back to back; each name as
// its (offset, length) in the table.
struct StringTable {
  std::string bytes;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> part_names, shape_names;
};

StringTable BuildStringTable(const Rig& rig, const std::string& path) {
  StringTable table;
  auto add_name = [&](std::string_view name, auto& names) {
    names.emplace_back(CheckedU32(table.bytes.size(), "string table size", path),
                       CheckedU32(name.size(), "name length", path));
    table.bytes += name;
  };
  for (const Part& part : rig.parts()) add_name(part.name, table.part_names);
  for (std::size_t s = 0; s < rig.shape_count(); ++s) add_name(rig.shape_name(s), table.shape_names);
  CheckedU32(table.bytes.size(), "string table size", path);
  return table;
}

// Which sections the file holds, their element counts and where they start.
struct Layout {
  std::array<std::uint64_t, kSectionKindCount> counts{};
  std::array<bool, kSectionKindCount> present{};
  std::array<std::uint64_t, kSectionKindCount> offsets{};
  std::uint32_t section_count = 0;
  std::uint64_t file_size = 0;

  Cursor At(std::byte* file, Section k) const { return Cursor(file + offsets[k]); }
};

// Header, table, then each present section at the next multiple of 16.
Layout PlanLayout(const Rig& rig, std::uint64_t string_bytes) {
  const bool has_uvs = !rig.uvs().empty();
  const bool has_normal_deltas = rig.has_normal_deltas();
  const std::uint64_t entry_count = rig.total_shape_entries();
  Layout layout;
  std::array<std::uint64_t, kSectionKindCount>& counts = layout.counts;
  counts[kMeta] = 1;
  counts[kPositions] = rig.vertex_count();
  counts[kNormals] = rig.vertex_count();
  counts[kTriangles] = rig.triangle_count();
  counts[kUvs] = has_uvs ? rig.vertex_count() : 0;
  counts[kParts] = rig.parts().size();
  counts[kShapes] = rig.shape_count();
  counts[kShapeIndices] = entry_count;
  counts[kShapePositions] = entry_count;
  counts[kShapeNormals] = has_normal_deltas ? entry_count : 0;
  counts[kStrings] = string_bytes;
  for (std::size_t k = 0; k < kSectionKindCount; ++k) layout.present[k] = kSectionKinds[k].required;
  layout.present[kUvs] = has_uvs;
  layout.present[kShapeNormals] = has_normal_deltas;

  for (bool p : layout.present) layout.section_count += p ? 1u : 0u;
  std::uint64_t end = kHeaderSize + kTableEntrySize * layout.section_count;
  for (std::size_t k = 0; k < kSectionKindCount; ++k) {
    if (!layout.present[k]) continue;
    layout.offsets[k] = AlignUp(end);
    end = layout.offsets[k] + counts[k] * kSectionKinds[k].element_size;
  }
  layout.file_size = end;
  return layout;
}

void WriteHeaderAndTable(const Layout& layout, std::byte* file) {
  Cursor header(file);
  header.Bytes("FRIG");
  header.U32(kFrigVersion);
  header.U32(layout.section_count);
  header.U32(0);  // CRC, filled in last
  header.U64(layout.file_size);
  header.U64(0);
  Cursor table(file + kHeaderSize);
  for (std::size_t k = 0; k < kSectionKindCount; ++k) {
    if (!layout.present[k]) continue;
    table.U32(kSectionKinds[k].tag);
    table.U32(kSectionKinds[k].element_size);
    table.U64(layout.counts[k]);
    table.U64(layout.offsets[k]);
    table.U64(layout.counts[k] * kSectionKinds[k].element_size);
  }
}

void WriteMeta(const Rig& rig, Cursor meta, const std::string& path) {
  const bool has_uvs = !rig.uvs().empty();
  const bool has_normal_deltas = rig.has_normal_deltas();
  meta.U32(static_cast<std::uint32_t>(rig.vertex_count()));
  meta.U32(CheckedU32(rig.triangle_count(), "triangle count", path));
  meta.U32(CheckedU32(rig.shape_count(), "shape count", path));
  meta.U32(CheckedU32(rig.parts().size(), "part count", path));
  meta.U32(CheckedU32(rig.total_shape_entries(), "shape entry count", path));
  meta.U32(static_cast<std::uint32_t>(rig.units()));
  meta.U32(static_cast<std::uint32_t>(rig.up_axis()));
  meta.U32((has_uvs ? kFlagHasUvs : 0u) | (has_normal_deltas ? kFlagHasNormalDeltas : 0u));
}

// Positions, normals, triangles and UVs.
void WriteMeshSections(const Rig& rig, const Layout& layout, std::byte* file) {
  Cursor positions = layout.At(file, kPositions);
  for (const glm::vec3& p : rig.positions()) positions.Vec3(p);
  Cursor normals = layout.At(file, kNormals);
  for (const glm::vec3& n : rig.normals()) normals.Vec3(n);
  Cursor triangles = layout.At(file, kTriangles);
  for (const Triangle& t : rig.triangles()) {
    for (std::uint32_t v : t) triangles.U32(v);
  }
  if (layout.present[kUvs]) {
    Cursor uvs = layout.At(file, kUvs);
    for (const glm::vec2& uv : rig.uvs()) uvs.Vec2(uv);
  }
}

void WriteParts(const Rig& rig, const StringTable& strings, Cursor parts) {
  for (std::size_t i = 0; i < rig.parts().size(); ++i) {
    parts.U32(strings.part_names[i].first);
    parts.U32(strings.part_names[i].second);
    parts.U32(rig.parts()[i].first_triangle);
    parts.U32(rig.parts()[i].triangle_count);
  }
}

// Shapes are written from their views, so the entries tile SIDX in shape
// order whatever the rig's internal ranges are.
void WriteShapes(const Rig& rig, const StringTable& strings, const Layout& layout, std::byte* file) {
  const bool has_normal_deltas = layout.present[kShapeNormals];
  Cursor shapes = layout.At(file, kShapes);
  Cursor indices = layout.At(file, kShapeIndices);
  Cursor position_deltas = layout.At(file, kShapePositions);
  Cursor normal_deltas = has_normal_deltas ? layout.At(file, kShapeNormals) : Cursor(nullptr);
  std::uint32_t next_entry = 0;
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    const BlendShapeView view = rig.shape(s);
    const auto count = static_cast<std::uint32_t>(view.vertex_indices.size());
    shapes.U32(strings.shape_names[s].first);
    shapes.U32(strings.shape_names[s].second);
    shapes.U32(next_entry);
    shapes.U32(count);
    next_entry += count;
    for (std::uint32_t v : view.vertex_indices) indices.U32(v);
    for (const glm::vec3& d : view.position_deltas) position_deltas.Vec3(d);
    if (has_normal_deltas) {
      for (const glm::vec3& d : view.normal_deltas) normal_deltas.Vec3(d);
    }
  }
}

std::vector<std::byte> Serialize(const Rig& rig, const std::string& path) {
  if (rig.vertex_count() == 0) {
    throw IoError(IoErrorKind::kInvalidRig, path, "the rig has no vertices (empty or moved-from)");
  }
  const StringTable strings = BuildStringTable(rig, path);
  const Layout layout = PlanLayout(rig, strings.bytes.size());

  std::vector<std::byte> bytes(static_cast<std::size_t>(layout.file_size));  // padding stays 0
  std::byte* file = bytes.data();
  WriteHeaderAndTable(layout, file);
  WriteMeta(rig, layout.At(file, kMeta), path);
  WriteMeshSections(rig, layout, file);
  WriteParts(rig, strings, layout.At(file, kParts));
  WriteShapes(rig, strings, layout, file);
  layout.At(file, kStrings).Bytes(strings.bytes);

  Store32(bytes.data() + kCrcAt, Crc32(std::span(bytes).subspan(kHeaderSize)));
  return bytes;
}

// ---------------------------------------------------------------- reading --

struct SectionRef {
  bool present = false;
  std::uint64_t table_entry = 0;  // file offset of its section table entry
  std::uint64_t count = 0;
  std::uint64_t offset = 0;
};

struct NamedRange {
  std::uint32_t name_offset;
  std::uint32_t name_length;
  std::uint32_t first;
  std::uint32_t count;
};

struct Meta {
  std::uint32_t vertex_count;
  std::uint32_t triangle_count;
  std::uint32_t shape_count;
  std::uint32_t part_count;
  std::uint32_t entry_count;
  std::uint32_t units;
  std::uint32_t up_axis;
  std::uint32_t flags;
};

class Parser {
 public:
  Parser(std::span<const std::byte> bytes, const std::string& path) : bytes_(bytes), path_(path) {}

  Rig Parse() {
    CheckHeader();
    ReadSectionTable();
    ReadMeta();
    CheckCounts();
    // Every count is now bounded by the file size, so decoding may allocate.
    Decode();
    CheckIndices();
    CheckFinite();
    CheckShapeOrder();
    return Build();
  }

 private:
  [[noreturn]] void Fail(IoErrorKind kind, std::uint64_t offset, std::string message) const {
    throw IoError(kind, path_, std::move(message), 0, static_cast<std::int64_t>(offset));
  }

  const std::byte* At(std::uint64_t offset) const { return bytes_.data() + offset; }

  void CheckHeader() {
    const std::uint64_t size = bytes_.size();
    if (size == 0) Fail(IoErrorKind::kEmpty, 0, "empty file (0 bytes), not a .frig file");
    if (size < kHeaderSize) {
      Fail(IoErrorKind::kTruncated, size,
           "file of " + std::to_string(size) + " bytes is shorter than the 32-byte .frig header");
    }
    if (Load32(At(kMagicAt)) != MakeTag("FRIG")) {
      Fail(IoErrorKind::kBadMagic, kMagicAt,
           "not a .frig file (magic " + TagName(Load32(At(kMagicAt))) + ", expected 'FRIG')");
    }
    const std::uint32_t version = Load32(At(kVersionAt));
    if (version != kFrigVersion) {
      Fail(IoErrorKind::kUnsupportedVersion, kVersionAt,
           ".frig version " + std::to_string(version) + " is not supported; this build reads version " +
               std::to_string(kFrigVersion));
    }
    const std::uint64_t declared_size = Load64(At(kFileSizeAt));
    if (declared_size != size) {
      Fail(IoErrorKind::kTruncated, kFileSizeAt,
           "header declares " + std::to_string(declared_size) + " bytes but the file has " +
               std::to_string(size) + (declared_size > size ? " (truncated)" : " (trailing bytes)"));
    }
    const std::uint32_t stored_crc = Load32(At(kCrcAt));
    const std::uint32_t actual_crc = Crc32(bytes_.subspan(kHeaderSize));
    if (stored_crc != actual_crc) {
      Fail(IoErrorKind::kChecksumMismatch, kCrcAt,
           "checksum mismatch: header says " + Hex32(stored_crc) + ", data has " + Hex32(actual_crc));
    }
  }

  void ReadSectionTable() {
    const std::uint64_t size = bytes_.size();
    const std::uint32_t section_count = Load32(At(kSectionCountAt));
    const std::uint64_t table_end = kHeaderSize + kTableEntrySize * section_count;
    if (table_end > size) {
      Fail(IoErrorKind::kAbsurdCount, kSectionCountAt,
           std::to_string(section_count) + " sections need a table of " +
               std::to_string(table_end - kHeaderSize) + " bytes but the file has " +
               std::to_string(size));
    }
    for (std::uint32_t i = 0; i < section_count; ++i) {
      const std::uint64_t entry = kHeaderSize + kTableEntrySize * i;
      const std::uint32_t tag = Load32(At(entry + kEntryTagAt));
      const std::uint32_t element_size = Load32(At(entry + kEntryElementSizeAt));
      const std::uint64_t count = Load64(At(entry + kEntryCountAt));
      const std::uint64_t offset = Load64(At(entry + kEntryOffsetAt));
      const std::uint64_t byte_size = Load64(At(entry + kEntryByteSizeAt));
      auto name = [tag] { return "section " + TagName(tag); };  // only on failure
      if (offset % kSectionAlignment != 0 || offset < table_end) {
        Fail(IoErrorKind::kParse, entry + kEntryOffsetAt,
             name() + " offset " + std::to_string(offset) +
                 " is not a multiple of 16 at or after the section table's end (" +
                 std::to_string(table_end) + ")");
      }
      if (offset > size || byte_size > size - offset) {
        Fail(IoErrorKind::kTruncated, entry + kEntryByteSizeAt,
             name() + " of " + std::to_string(byte_size) + " bytes at offset " + std::to_string(offset) +
                 " ends past the end of the file (" + std::to_string(size) + " bytes)");
      }
      const std::optional<Section> kind = FindSectionKind(tag);
      if (element_size == 0 || (kind && element_size != kSectionKinds[*kind].element_size)) {
        Fail(IoErrorKind::kParse, entry + kEntryElementSizeAt,
             name() + " has element size " + std::to_string(element_size) +
                 (kind ? ", expected " + std::to_string(kSectionKinds[*kind].element_size) : ""));
      }
      // Division, not multiplication, so that a huge count cannot wrap around.
      if (count != byte_size / element_size || byte_size % element_size != 0) {
        Fail(IoErrorKind::kAbsurdCount, entry + kEntryCountAt,
             name() + " declares " + std::to_string(count) + " elements of " +
                 std::to_string(element_size) + " bytes but holds " + std::to_string(byte_size) +
                 " bytes");
      }
      if (!kind) continue;  // unknown: skipped, for forward compatibility
      SectionRef& ref = sections_[*kind];
      if (ref.present) Fail(IoErrorKind::kParse, entry + kEntryTagAt, name() + " appears twice");
      ref = {true, entry, count, offset};
    }
    for (std::size_t k = 0; k < kSectionKindCount; ++k) {
      if (kSectionKinds[k].required && !sections_[k].present) {
        Fail(IoErrorKind::kParse, kHeaderSize,
             "required section " + TagName(kSectionKinds[k].tag) + " is missing");
      }
    }
  }

  void ReadMeta() {
    const SectionRef& ref = sections_[kMeta];
    if (ref.count != 1) {
      Fail(IoErrorKind::kParse, ref.table_entry + kEntryCountAt,
           "section 'META' holds " + std::to_string(ref.count) + " elements, expected 1");
    }
    const std::byte* p = At(ref.offset);
    meta_ = {Load32(p),      Load32(p + 4),  Load32(p + 8),  Load32(p + 12),
             Load32(p + 16), Load32(p + 20), Load32(p + 24), Load32(p + 28)};
    if (meta_.units > kMaxUnits) {
      Fail(IoErrorKind::kParse, ref.offset + 20, "unknown units code " + std::to_string(meta_.units));
    }
    if (meta_.up_axis > kMaxUpAxis) {
      Fail(IoErrorKind::kParse, ref.offset + 24, "unknown up axis code " + std::to_string(meta_.up_axis));
    }
    if ((meta_.flags & ~kKnownFlags) != 0) {
      Fail(IoErrorKind::kParse, ref.offset + 28, "unknown flags " + Hex32(meta_.flags));
    }
  }

  void ExpectCount(Section k, std::uint64_t expected, const char* what) const {
    const SectionRef& ref = sections_[k];
    const std::uint64_t found = ref.present ? ref.count : 0;
    if (found != expected) {
      const std::uint64_t offset =
          ref.present ? ref.table_entry + kEntryCountAt : sections_[kMeta].offset + 28;
      Fail(IoErrorKind::kAbsurdCount, offset,
           "section " + TagName(kSectionKinds[k].tag) + " holds " + std::to_string(found) +
               " elements but META declares " + what + " " + std::to_string(expected));
    }
  }

  void CheckCounts() const {
    const bool has_uvs = (meta_.flags & kFlagHasUvs) != 0;
    const bool has_normal_deltas = (meta_.flags & kFlagHasNormalDeltas) != 0;
    if (sections_[kUvs].present != has_uvs || sections_[kShapeNormals].present != has_normal_deltas) {
      Fail(IoErrorKind::kParse, sections_[kMeta].offset + 28,
           "META flags " + Hex32(meta_.flags) + " disagree with the optional sections present");
    }
    ExpectCount(kPositions, meta_.vertex_count, "vertex_count");
    ExpectCount(kNormals, meta_.vertex_count, "vertex_count");
    ExpectCount(kTriangles, meta_.triangle_count, "triangle_count");
    ExpectCount(kUvs, has_uvs ? meta_.vertex_count : 0, "vertex_count");
    ExpectCount(kParts, meta_.part_count, "part_count");
    ExpectCount(kShapes, meta_.shape_count, "shape_count");
    ExpectCount(kShapeIndices, meta_.entry_count, "shape_entry_count");
    ExpectCount(kShapePositions, meta_.entry_count, "shape_entry_count");
    ExpectCount(kShapeNormals, has_normal_deltas ? meta_.entry_count : 0, "shape_entry_count");
  }

  std::vector<glm::vec3> DecodeVec3(Section k) const {
    const auto count = static_cast<std::size_t>(sections_[k].count);
    std::vector<glm::vec3> out;
    out.reserve(count);  // not resize: no zero fill of memory about to be overwritten
    const std::byte* p = At(sections_[k].offset);
    for (std::size_t i = 0; i < count; ++i, p += 12) {
      out.emplace_back(LoadFloat(p), LoadFloat(p + 4), LoadFloat(p + 8));
    }
    return out;
  }

  std::vector<NamedRange> DecodeRanges(Section k) const {
    std::vector<NamedRange> out(static_cast<std::size_t>(sections_[k].count));
    const std::byte* p = At(sections_[k].offset);
    for (NamedRange& r : out) {
      r = {Load32(p), Load32(p + 4), Load32(p + 8), Load32(p + 12)};
      p += 16;
    }
    return out;
  }

  void Decode() {
    raw_.positions = DecodeVec3(kPositions);
    raw_.normals = DecodeVec3(kNormals);
    raw_.triangles.resize(meta_.triangle_count);
    const std::byte* p = At(sections_[kTriangles].offset);
    for (Triangle& t : raw_.triangles) {
      t = {Load32(p), Load32(p + 4), Load32(p + 8)};
      p += 12;
    }
    if (sections_[kUvs].present) {
      raw_.uvs.resize(meta_.vertex_count);
      p = At(sections_[kUvs].offset);
      for (glm::vec2& uv : raw_.uvs) {
        uv = {LoadFloat(p), LoadFloat(p + 4)};
        p += 8;
      }
    }
    parts_ = DecodeRanges(kParts);
    shapes_ = DecodeRanges(kShapes);
    indices_.resize(meta_.entry_count);
    p = At(sections_[kShapeIndices].offset);
    for (std::uint32_t& v : indices_) {
      v = Load32(p);
      p += 4;
    }
    position_deltas_ = DecodeVec3(kShapePositions);
    if (sections_[kShapeNormals].present) normal_deltas_ = DecodeVec3(kShapeNormals);
    raw_.units = static_cast<Units>(meta_.units);
    raw_.up_axis = static_cast<UpAxis>(meta_.up_axis);
  }

  // File offset of field `field` (4 bytes each) of element `i` of section k.
  std::uint64_t FieldAt(Section k, std::size_t i, std::size_t field) const {
    return sections_[k].offset + kSectionKinds[k].element_size * std::uint64_t{i} + 4 * field;
  }

  // Names must lie within STRS and, together, be no longer than it, so that a
  // small file cannot ask for huge strings by repeating one long name.
  void CheckNames(Section k, const std::vector<NamedRange>& ranges, std::uint64_t& total_length) const {
    const std::uint64_t strings_size = sections_[kStrings].count;
    for (std::size_t i = 0; i < ranges.size(); ++i) {
      const NamedRange& r = ranges[i];
      total_length += r.name_length;
      if (std::uint64_t{r.name_offset} + r.name_length > strings_size || total_length > strings_size) {
        Fail(IoErrorKind::kIndexOutOfRange, FieldAt(k, i, 0),
             TagName(kSectionKinds[k].tag) + " element " + std::to_string(i) + ": name [" +
                 std::to_string(r.name_offset) + ", +" + std::to_string(r.name_length) +
                 ") is outside the string table of " + std::to_string(strings_size) +
                 " bytes or names overlap");
      }
    }
  }

  void CheckIndices() const {
    const std::uint32_t n = meta_.vertex_count;
    for (std::size_t t = 0; t < raw_.triangles.size(); ++t) {
      for (std::size_t c = 0; c < 3; ++c) {
        if (raw_.triangles[t][c] >= n) {
          Fail(IoErrorKind::kIndexOutOfRange, FieldAt(kTriangles, t, c),
               "triangle " + std::to_string(t) + " uses vertex " +
                   std::to_string(raw_.triangles[t][c]) + " >= vertex count " + std::to_string(n));
        }
      }
    }
    std::uint64_t name_bytes = 0;
    CheckNames(kParts, parts_, name_bytes);
    CheckNames(kShapes, shapes_, name_bytes);
    for (std::size_t i = 0; i < parts_.size(); ++i) {
      if (std::uint64_t{parts_[i].first} + parts_[i].count > meta_.triangle_count) {
        Fail(IoErrorKind::kIndexOutOfRange, FieldAt(kParts, i, 2),
             "part " + std::to_string(i) + " triangles [" + std::to_string(parts_[i].first) + ", +" +
                 std::to_string(parts_[i].count) + ") exceed the triangle count " +
                 std::to_string(meta_.triangle_count));
      }
    }
    std::uint64_t next_entry = 0;
    for (std::size_t s = 0; s < shapes_.size(); ++s) {
      const NamedRange& r = shapes_[s];
      if (std::uint64_t{r.first} + r.count > meta_.entry_count) {
        Fail(IoErrorKind::kIndexOutOfRange, FieldAt(kShapes, s, 2),
             "shape " + std::to_string(s) + " entries [" + std::to_string(r.first) + ", +" +
                 std::to_string(r.count) + ") exceed the " + std::to_string(meta_.entry_count) +
                 " entries of 'SIDX'");
      }
      // Tiling keeps the loaded rig no larger than the file.
      if (r.first != next_entry) {
        Fail(IoErrorKind::kParse, FieldAt(kShapes, s, 2),
             "shape " + std::to_string(s) + " entries start at " + std::to_string(r.first) +
                 ", expected " + std::to_string(next_entry) + " (shapes must tile 'SIDX' in order)");
      }
      next_entry += r.count;
    }
    if (next_entry != meta_.entry_count) {
      Fail(IoErrorKind::kParse, sections_[kShapes].offset,
           "shapes cover " + std::to_string(next_entry) + " of " +
               std::to_string(meta_.entry_count) + " entries of 'SIDX'");
    }
    for (std::size_t i = 0; i < indices_.size(); ++i) {
      if (indices_[i] >= n) {
        Fail(IoErrorKind::kIndexOutOfRange, FieldAt(kShapeIndices, i, 0),
             "shape entry " + std::to_string(i) + " uses vertex " + std::to_string(indices_[i]) +
                 " >= vertex count " + std::to_string(n));
      }
    }
  }

  template <int N, typename Vec>
  void CheckFinite(Section k, const std::vector<Vec>& values, const char* what) const {
    for (std::size_t i = 0; i < values.size(); ++i) {
      for (int c = 0; c < N; ++c) {
        if (!std::isfinite(values[i][c])) {
          Fail(IoErrorKind::kNonFinite, FieldAt(k, i, static_cast<std::size_t>(c)),
               std::string(what) + " " + std::to_string(i) + " is not finite");
        }
      }
    }
  }

  void CheckFinite() const {
    CheckFinite<3>(kPositions, raw_.positions, "position");
    CheckFinite<3>(kNormals, raw_.normals, "normal");
    CheckFinite<2>(kUvs, raw_.uvs, "UV");
    CheckFinite<3>(kShapePositions, position_deltas_, "shape position delta");
    CheckFinite<3>(kShapeNormals, normal_deltas_, "shape normal delta");
  }

  void CheckShapeOrder() const {
    for (std::size_t s = 0; s < shapes_.size(); ++s) {
      const NamedRange& r = shapes_[s];
      for (std::uint64_t i = std::uint64_t{r.first} + 1; i < std::uint64_t{r.first} + r.count; ++i) {
        if (indices_[i] <= indices_[i - 1]) {
          Fail(IoErrorKind::kParse, FieldAt(kShapeIndices, static_cast<std::size_t>(i), 0),
               "shape " + std::to_string(s) + ": vertex index " + std::to_string(indices_[i]) +
                   " follows " + std::to_string(indices_[i - 1]) + " (must be strictly increasing)");
        }
      }
    }
  }

  std::string Name(const NamedRange& r) const {
    const auto* text = reinterpret_cast<const char*>(At(sections_[kStrings].offset + r.name_offset));
    return std::string(text, r.name_length);
  }

  Rig Build() {
    for (const NamedRange& r : parts_) raw_.parts.push_back({Name(r), r.first, r.count});
    raw_.shapes.reserve(shapes_.size());
    for (const NamedRange& r : shapes_) {
      RawBlendShape shape;
      shape.name = Name(r);
      shape.vertex_indices.assign(indices_.begin() + r.first, indices_.begin() + r.first + r.count);
      shape.position_deltas.assign(position_deltas_.begin() + r.first,
                                   position_deltas_.begin() + r.first + r.count);
      if (!normal_deltas_.empty()) {
        shape.normal_deltas.assign(normal_deltas_.begin() + r.first,
                                   normal_deltas_.begin() + r.first + r.count);
      }
      raw_.shapes.push_back(std::move(shape));
    }
    // Free the flat copies before the builder makes its own.
    indices_ = {};
    position_deltas_ = {};
    normal_deltas_ = {};
    std::string problem;
    std::optional<Rig> rig = RigBuilder::Build(std::move(raw_), &problem);
    if (!rig) Fail(IoErrorKind::kInvalidRig, kHeaderSize, "the rig is invalid: " + problem);
    return std::move(*rig);
  }

  std::span<const std::byte> bytes_;
  const std::string& path_;
  std::array<SectionRef, kSectionKindCount> sections_{};
  Meta meta_{};
  RawRig raw_;
  std::vector<NamedRange> parts_;
  std::vector<NamedRange> shapes_;
  std::vector<std::uint32_t> indices_;
  std::vector<glm::vec3> position_deltas_;
  std::vector<glm::vec3> normal_deltas_;
};

}  // namespace

std::uint32_t Crc32(std::span<const std::byte> bytes) {
  // Raw pointers: span iterators make unoptimised (sanitizer) builds several times slower.
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  const unsigned char* const end = p + bytes.size();
  const auto& t = kCrcTables;
  std::uint32_t crc = 0xFFFFFFFFu;
  auto word = [](const unsigned char* q) {
    return std::uint32_t{q[0]} | std::uint32_t{q[1]} << 8 | std::uint32_t{q[2]} << 16 |
           std::uint32_t{q[3]} << 24;
  };
  for (; end - p >= 8; p += 8) {
    const std::uint32_t lo = crc ^ word(p);
    const std::uint32_t hi = word(p + 4);
    crc = t[7][lo & 0xFFu] ^ t[6][(lo >> 8) & 0xFFu] ^ t[5][(lo >> 16) & 0xFFu] ^ t[4][lo >> 24] ^
          t[3][hi & 0xFFu] ^ t[2][(hi >> 8) & 0xFFu] ^ t[1][(hi >> 16) & 0xFFu] ^ t[0][hi >> 24];
  }
  for (; p != end; ++p) crc = t[0][(crc ^ *p) & 0xFFu] ^ (crc >> 8);
  return crc ^ 0xFFFFFFFFu;
}

Rig ParseFrig(std::span<const std::byte> bytes, const std::string& path_for_errors) {
  return Parser(bytes, path_for_errors).Parse();
}

Rig ReadFrig(const std::filesystem::path& path) {
  const std::vector<std::byte> bytes = ReadInputFile(path);
  return ParseFrig(bytes, path.string());
}

std::vector<std::byte> SerializeFrig(const Rig& rig) { return Serialize(rig, std::string()); }

void WriteFrig(const std::filesystem::path& path, const Rig& rig) {
  // Serialised in full before the file is touched, so a failure leaves it as it was.
  const std::vector<std::byte> bytes = Serialize(rig, path.string());
  WriteFileAtomically(path, bytes);
}

}  // namespace facerig
