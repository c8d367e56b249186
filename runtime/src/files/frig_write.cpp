// SerializeFrig and WriteFrig: a rig as .frig v1 bytes.
#include "facerig/runtime/files/frig.h"

#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "files/frig_format.h"
#include "files/frig_materials.h"

namespace facerig {
namespace {

using namespace frig_format;  // the layout shared with the reader

std::uint32_t CheckedU32(std::uint64_t value, const char* what, const std::string& path) {
  if (value > std::numeric_limits<std::uint32_t>::max()) {
    throw IoError(IoErrorKind::kInvalidRig, path,
                  std::string(what) + " " + std::to_string(value) + " does not fit in .frig v1");
  }
  return static_cast<std::uint32_t>(value);
}

// The string table: part, shape, material and image names, back to back;
// each name as its (offset, length) in the table.
struct StringTable {
  std::string bytes;
  std::vector<NameRef> part_names, shape_names, material_names, image_names;
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
  for (const Material& material : rig.materials()) add_name(material.name, table.material_names);
  for (const EncodedImage& image : rig.images()) add_name(image.name, table.image_names);
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
  PlanMaterialSections(rig, counts, layout.present);

  for (bool p : layout.present) layout.section_count += p ? 1u : 0u;
  std::uint64_t end = kHeaderSize + kTableEntrySize * layout.section_count;
  for (std::size_t k = 0; k < kSectionKindCount; ++k) {
    if (!layout.present[k]) continue;
    layout.offsets[k] = AlignUp(end, kSectionAlignment);
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
  CheckMaterialsWritable(rig, path);
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
  WriteMaterialSections(rig, strings.material_names, strings.image_names, layout.offsets, file);

  Store32(bytes.data() + kCrcAt, Crc32(std::span(bytes).subspan(kHeaderSize)));
  return bytes;
}

}  // namespace

std::vector<std::byte> SerializeFrig(const Rig& rig) { return Serialize(rig, std::string()); }

void WriteFrig(const std::filesystem::path& path, const Rig& rig) {
  // Serialised in full before the file is touched, so a failure leaves it as it was.
  const std::vector<std::byte> bytes = Serialize(rig, path.string());
  WriteFileAtomically(path, bytes);
}

}  // namespace facerig
