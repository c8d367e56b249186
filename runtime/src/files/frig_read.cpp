// ParseFrig and ReadFrig: a rig from .frig v1 bytes, every field checked
// before it is used.
#include "facerig/runtime/files/frig.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/runtime/rig_builder.h"
#include "files/frig_format.h"
#include "files/frig_materials.h"

namespace facerig {
namespace {

using namespace frig_format;  // the layout shared with the writer

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
    materials_ = ReadFrigMaterials(bytes_, sections_, meta_.part_count, name_bytes_, path_);
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
    CheckMaterialCounts(sections_, meta_.part_count, path_);
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

  void CheckIndices() {
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
    CheckNames(kParts, parts_, name_bytes_);
    CheckNames(kShapes, shapes_, name_bytes_);
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
      // The ranges were checked against indices_.size(), so they fit in size_t.
      const auto first = static_cast<std::size_t>(r.first), end = first + static_cast<std::size_t>(r.count);
      for (std::size_t i = first + 1; i < end; ++i) {
        if (indices_[i] <= indices_[i - 1]) {
          Fail(IoErrorKind::kParse, FieldAt(kShapeIndices, i, 0),
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
    for (std::size_t i = 0; i < parts_.size(); ++i) {
      raw_.parts.push_back({Name(parts_[i]), parts_[i].first, parts_[i].count, materials_.part_materials[i]});
    }
    raw_.materials = std::move(materials_.materials);
    raw_.images = std::move(materials_.images);
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
  SectionRefs sections_{};
  Meta meta_{};
  RawRig raw_;
  std::vector<NamedRange> parts_;
  std::vector<NamedRange> shapes_;
  std::vector<std::uint32_t> indices_;
  std::vector<glm::vec3> position_deltas_;
  std::vector<glm::vec3> normal_deltas_;
  std::uint64_t name_bytes_ = 0;  // of the part and shape names, bounded by 'STRS'
  FrigMaterials materials_;
};

}  // namespace

Rig ParseFrig(std::span<const std::byte> bytes, const std::string& path_for_errors) {
  return Parser(bytes, path_for_errors).Parse();
}

Rig ReadFrig(const std::filesystem::path& path) {
  const std::vector<std::byte> bytes = ReadInputFile(path);
  return ParseFrig(bytes, path.string());
}

}  // namespace facerig
