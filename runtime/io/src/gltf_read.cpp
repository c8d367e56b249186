// ReadGltf and ParseGltf: a rig from the mesh of a glTF document.
#include "facerig/runtime/io/gltf.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <tiny_gltf.h>

#include "facerig/runtime/error.h"
#include "facerig/runtime/rig_builder.h"
#include "gltf_internal.h"
#include "facerig/runtime/files/image_file.h"
#include "gltf_reader.h"

namespace facerig::gltf_internal {

const tinygltf::Value& Member(const tinygltf::Value& object, const char* key) {
  static const tinygltf::Value kNull;
  return object.Has(key) ? object.Get(key) : kNull;
}

std::string StringOr(const tinygltf::Value& array, std::size_t index, std::string fallback) {
  if (array.IsArray() && index < array.ArrayLen()) {
    const tinygltf::Value& value = array.Get(static_cast<int>(index));
    if (value.IsString() && !value.Get<std::string>().empty()) return value.Get<std::string>();
  }
  return fallback;
}

// A part name for primitive p of a mesh with `part_count` parts:
// extras.facerig.parts, else the mesh's (or node's) name `base`, with the
// primitive's material name (or "primitive<p>") when it has several parts.
std::string PartName(const tinygltf::Model& model, const tinygltf::Mesh& mesh, const std::string& base,
                     std::size_t p, std::size_t part_count) {
  const tinygltf::Value& part_names = Member(Member(mesh.extras, "facerig"), "parts");
  const int material = mesh.primitives[p].material;
  const bool named = material >= 0 && static_cast<std::size_t>(material) < model.materials.size() &&
                     !model.materials[static_cast<std::size_t>(material)].name.empty();
  const std::string suffix = named ? model.materials[static_cast<std::size_t>(material)].name : "primitive" + std::to_string(p);
  const std::string fallback = base.empty() ? suffix : part_count == 1 ? base : base + "." + suffix;
  return StringOr(part_names, p, fallback);
}

// Positions of every vertex block, back to back; normals and UVs only when
// every block has them.
void GltfReader::ReadVertices(const std::vector<VertexBlock>& blocks, RawRig* raw) const {
  bool all_normals = true, all_uvs = true;
  for (const VertexBlock& block : blocks) {
    all_normals = all_normals && block.primitive->attributes.count("NORMAL") > 0;
    all_uvs = all_uvs && block.primitive->attributes.count("TEXCOORD_0") > 0;
  }
  const GltfAccessors accessors = Accessors();
  for (const VertexBlock& block : blocks) {
    const std::string what = "accessor " + std::to_string(block.position_accessor) + " (POSITION)";
    VecData<glm::vec3> positions = accessors.ReadVectors<glm::vec3>(block.position_accessor, std::nullopt, false, what);
    raw->positions.insert(raw->positions.end(), positions.values.begin(), positions.values.end());
    if (all_normals) {
      VecData<glm::vec3> normals = accessors.ReadVectors<glm::vec3>(block.primitive->attributes.at("NORMAL"),
                                                                    block.vertex_count, false, "NORMAL");
      raw->normals.insert(raw->normals.end(), normals.values.begin(), normals.values.end());
    }
    if (all_uvs) {
      VecData<glm::vec2> uvs = accessors.ReadVectors<glm::vec2>(block.primitive->attributes.at("TEXCOORD_0"),
                                                                block.vertex_count, false, "TEXCOORD_0");
      for (glm::vec2& uv : uvs.values) uv.y = 1.0f - uv.y;
      raw->uvs.insert(raw->uvs.end(), uvs.values.begin(), uvs.values.end());
    }
  }
  if (raw->positions.empty()) Fail(IoErrorKind::kEmpty, "the mesh has no vertices");
}

// Parts: one per primitive, named from extras.facerig.parts when present;
// which primitive each part is into part_primitives.
void GltfReader::ReadParts(const tinygltf::Mesh& mesh, const MeshVertices& vertices, RawRig* raw,
                           std::vector<std::size_t>* part_primitives) const {
  const tinygltf::Value& part_names = Member(Member(mesh.extras, "facerig"), "parts");
  for (std::size_t p : vertices.triangle_primitives) {
    const tinygltf::Primitive& primitive = mesh.primitives[p];
    const VertexBlock& block =
        vertices.blocks[vertices.block_of_accessor.at(primitive.attributes.at("POSITION"))];
    const std::string what = "primitive " + std::to_string(p);
    const std::vector<std::uint32_t> indices = Accessors().ReadIndices(primitive, block, what);
    if (indices.empty()) continue;  // a part needs at least one triangle
    RawPart part;
    part.name = StringOr(part_names, p, "primitive" + std::to_string(p));
    part.first_triangle = static_cast<std::uint32_t>(raw->triangles.size());
    part.triangle_count = static_cast<std::uint32_t>(indices.size() / 3);
    for (std::size_t i = 0; i < indices.size(); i += 3) {
      raw->triangles.push_back({indices[i], indices[i + 1], indices[i + 2]});
    }
    raw->parts.push_back(std::move(part));
    part_primitives->push_back(p);
  }
  if (raw->triangles.empty()) Fail(IoErrorKind::kEmpty, "the mesh has no triangles");
}

// Units and up axis: ours when written by facerig, else glTF's metres and +Y.
void GltfReader::ReadFrame(const tinygltf::Mesh& mesh, RawRig* raw) const {
  const tinygltf::Value& facerig = Member(mesh.extras, "facerig");
  raw->units = Units::kMetres;
  raw->up_axis = UpAxis::kY;
  const tinygltf::Value& units = Member(facerig, "units");
  if (units.IsString()) {
    const std::optional<Units> parsed = ParseUnits(units.Get<std::string>());
    if (!parsed)
      Fail(IoErrorKind::kParse, "unknown units '" + units.Get<std::string>() + "' in extras.facerig");
    raw->units = *parsed;
  }
  const tinygltf::Value& up = Member(facerig, "up");
  if (up.IsString()) {
    const std::string axis = up.Get<std::string>();
    if (axis == "Z" || axis == "+Z") {
      raw->up_axis = UpAxis::kZ;
    } else if (axis != "Y" && axis != "+Y") {
      Fail(IoErrorKind::kParse, "unknown up axis '" + axis + "' in extras.facerig");
    }
  }
}

int GltfReader::ChosenMesh() const {
  const int mesh_index = ChooseMesh(model_);
  if (mesh_index < 0) Fail(IoErrorKind::kEmpty, "the file has no mesh");
  return mesh_index;
}

void GltfReader::ReadNeutral(const tinygltf::Mesh& mesh, const MeshVertices& vertices, RawRig* raw,
                             std::vector<std::size_t>* part_primitives) const {
  ReadVertices(vertices.blocks, raw);
  ReadParts(mesh, vertices, raw, part_primitives);
}

// The neutral read into `raw` as a Mesh, with part names from the mesh's (or
// its node's) name where extras.facerig.parts has none, and the materials.
Mesh GltfReader::NeutralMeshOf(int mesh_index, const RawRig& raw,
                               const std::vector<std::size_t>& part_primitives) const {
  const tinygltf::Mesh& gltf_mesh = model_.meshes[static_cast<std::size_t>(mesh_index)];
  std::string base = gltf_mesh.name;
  for (std::size_t n = 0; base.empty() && n < model_.nodes.size(); ++n) {
    if (model_.nodes[n].mesh == mesh_index) base = model_.nodes[n].name;
  }
  Mesh mesh = NeutralMesh(raw);
  bool any_material = false, any_without = false;
  for (std::size_t i = 0; i < part_primitives.size(); ++i) {
    const std::size_t p = part_primitives[i];
    mesh.part_names[i] = PartName(model_, gltf_mesh, base, p, part_primitives.size());
    (MaterialOf(gltf_mesh.primitives[p]) >= 0 ? any_material : any_without) = true;
  }
  if (!any_material) return mesh;
  ReadMaterials(&mesh);
  // glTF's default material (opaque white, single-sided) for primitives without one.
  const auto default_material = static_cast<std::uint32_t>(mesh.materials.size());
  if (any_without) mesh.materials.push_back(Material{.name = "default"});
  mesh.triangle_materials.resize(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const int material = MaterialOf(gltf_mesh.primitives[part_primitives[mesh.triangle_parts[t]]]);
    mesh.triangle_materials[t] = material >= 0 ? static_cast<std::uint32_t>(material) : default_material;
  }
  return mesh;
}

// The chosen mesh's vertices and triangles (no shapes yet).
GltfReader::Neutral GltfReader::ReadChosenNeutral() const {
  Neutral neutral;
  neutral.mesh_index = ChosenMesh();
  neutral.mesh = &model_.meshes[static_cast<std::size_t>(neutral.mesh_index)];
  neutral.vertices = GroupMeshVertices(model_, *neutral.mesh, path_, file_size_);
  ReadNeutral(*neutral.mesh, neutral.vertices, &neutral.raw, &neutral.part_primitives);
  neutral.rig_vertex = ReadRigVertices(neutral.vertices);
  if (!neutral.rig_vertex.empty()) WeldNeutral(neutral.rig_vertex, &neutral.raw);
  return neutral;
}

Mesh GltfReader::ReadMesh() {
  const Neutral neutral = ReadChosenNeutral();
  return NeutralMeshOf(neutral.mesh_index, neutral.raw, neutral.part_primitives);
}

Rig GltfReader::Read(Mesh* neutral) {
  Neutral chosen = ReadChosenNeutral();
  Mesh mesh = NeutralMeshOf(chosen.mesh_index, chosen.raw, chosen.part_primitives);
  RawRig& raw = chosen.raw;
  // The rig's parts are the mesh's (one per primitive), with their materials.
  for (std::size_t p = 0; p < raw.parts.size(); ++p) {
    raw.parts[p].name = mesh.part_names[p];
    if (!mesh.triangle_materials.empty()) {
      raw.parts[p].material = static_cast<std::int32_t>(mesh.triangle_materials[raw.parts[p].first_triangle]);
    }
  }
  if (!mesh.triangle_materials.empty()) {
    raw.materials = mesh.materials;
    raw.images = mesh.images;
  }
  if (neutral) *neutral = std::move(mesh);
  ReadShapes(*chosen.mesh, chosen.vertices.blocks, &raw);
  if (!chosen.rig_vertex.empty()) WeldShapes(chosen.rig_vertex, &raw);
  ReadFrame(*chosen.mesh, &raw);

  std::string problem;
  std::optional<Rig> rig = RigBuilder::Build(std::move(raw), &problem);
  if (!rig) Fail(IoErrorKind::kInvalidRig, problem);
  return std::move(*rig);
}

}  // namespace facerig::gltf_internal

namespace facerig {
namespace {

using gltf_internal::Format;
using gltf_internal::FormatFromExtension;
using gltf_internal::ParseModel;
using gltf_internal::GltfReader;

GltfReader ReaderOfFile(const std::filesystem::path& path) {
  const Format format = FormatFromExtension(path);
  std::uint64_t file_size = 0;
  tinygltf::Model model = ParseModel(path, format, &file_size, gltf_internal::Images::kKeepEncoded);
  gltf_internal::RefuseCompression(model, path.string());
  return GltfReader(path.string(), std::move(model), file_size);
}

GltfReader ReaderOfBytes(std::span<const std::byte> bytes, const std::filesystem::path& path) {
  const Format format = FormatFromExtension(path);
  tinygltf::Model model = gltf_internal::ParseModelBytes(
      {reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()}, path, format,
      gltf_internal::Images::kKeepEncoded);
  gltf_internal::RefuseCompression(model, path.string());
  return GltfReader(path.string(), std::move(model), bytes.size());
}

}  // namespace

namespace {

// The rig as a viewer shows the file: every mesh of its scene where it has
// several or moves them (ReadScene), else its mesh as it is.
Rig ReadSceneRig(GltfReader reader) {
  std::optional<Rig> scene = reader.ReadScene();
  return scene ? std::move(*scene) : reader.Read(nullptr);
}

}  // namespace

Rig ReadGltf(const std::filesystem::path& path) { return ReadSceneRig(ReaderOfFile(path)); }

Rig ReadGltf(const std::filesystem::path& path, Mesh* mesh) { return ReaderOfFile(path).Read(mesh); }

Rig ParseGltf(std::span<const std::byte> bytes, const std::filesystem::path& path) {
  return ReadSceneRig(ReaderOfBytes(bytes, path));
}

Mesh ReadGltfMesh(const std::filesystem::path& path) { return ReaderOfFile(path).ReadMesh(); }

Mesh ParseGltfMesh(std::span<const std::byte> bytes, const std::filesystem::path& path) {
  return ReaderOfBytes(bytes, path).ReadMesh();
}

}  // namespace facerig
