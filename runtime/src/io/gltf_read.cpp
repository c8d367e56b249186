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
#include "facerig/runtime/io/gltf_internal.h"
#include "facerig/runtime/io/image_file.h"
#include "gltf_accessors.h"
#include "gltf_components.h"
#include "gltf_scene.h"
#include "gltf_scene_skin.h"

namespace facerig {
namespace {

using gltf_internal::GltfAccessors;
using gltf_internal::VecData;

using gltf_internal::ChooseMesh;
using gltf_internal::Format;
using gltf_internal::FormatFromExtension;
using gltf_internal::GroupMeshVertices;
using gltf_internal::MeshVertices;
using gltf_internal::ParseModel;
using gltf_internal::VertexBlock;

class GltfReader {
 public:
  GltfReader(std::string path, tinygltf::Model model, std::uint64_t file_size)
      : path_(std::move(path)), model_(std::move(model)), file_size_(file_size) {}

  // The rig, and the neutral as a Mesh into *mesh when not null.
  Rig Read(Mesh* mesh);
  Mesh ReadMesh();
  // Every mesh of the scene in scene space (SceneMerger), for files that are
  // not one of facerig's: nullopt when the scene is one untransformed mesh or
  // facerig's own (Read then reads it as it is).
  std::optional<Rig> ReadScene() const;
  bool ReadsAsItIs(const gltf_internal::MeshInstance& only, const std::vector<glm::dmat4>& node_worlds) const;
  RawRig ReadScenePiece(const gltf_internal::MeshInstance& instance, const std::vector<glm::dmat4>& node_worlds,
                        std::int32_t default_material, bool* used_default) const;

 private:
  [[noreturn]] void Fail(IoErrorKind kind, const std::string& message) const {
    throw IoError(kind, path_, message);
  }

  RawBlendShape ReadShape(const std::vector<VertexBlock>& blocks, std::size_t target, std::string name,
                          bool with_normals) const;
  void ReadVertices(const std::vector<VertexBlock>& blocks, RawRig* raw) const;
  void ReadParts(const tinygltf::Mesh& mesh, const MeshVertices& vertices, RawRig* raw,
                 std::vector<std::size_t>* part_primitives) const;
  void ReadNeutral(const tinygltf::Mesh& mesh, const MeshVertices& vertices, RawRig* raw,
                   std::vector<std::size_t>* part_primitives) const;
  // The chosen mesh read up to its neutral: what both Read and ReadMesh need.
  struct Neutral {
    int mesh_index = -1;
    const tinygltf::Mesh* mesh = nullptr;
    MeshVertices vertices;
    RawRig raw;
    std::vector<std::size_t> part_primitives;
  };
  Neutral ReadChosenNeutral() const;
  Mesh NeutralMeshOf(int mesh_index, const RawRig& raw, const std::vector<std::size_t>& part_primitives) const;
  std::vector<std::int32_t> ReadImages(Mesh* mesh) const;
  // The document's images and every material, in its order, into *mesh.
  void ReadMaterials(Mesh* mesh) const;
  std::int32_t ImageOfTexture(int texture_index, const std::vector<std::int32_t>& kept) const;
  Material ReadMaterial(const tinygltf::Material& material, const std::vector<std::int32_t>& kept) const;
  int MaterialOf(const tinygltf::Primitive& primitive) const;
  int ChosenMesh() const;
  void ReadShapes(const tinygltf::Mesh& mesh, const std::vector<VertexBlock>& blocks, RawRig* raw) const;
  void ReadFrame(const tinygltf::Mesh& mesh, RawRig* raw) const;

  // A view of this reader's model and file (built per use: the reader may move).
  GltfAccessors Accessors() const { return GltfAccessors(path_, model_, file_size_); }

  std::string path_;
  tinygltf::Model model_;
  std::uint64_t file_size_;
};

RawBlendShape GltfReader::ReadShape(const std::vector<VertexBlock>& blocks, std::size_t target,
                                    std::string name, bool with_normals) const {
  RawBlendShape shape;
  shape.name = std::move(name);
  const std::string what = "morph target " + std::to_string(target) + " ('" + shape.name + "')";
  for (const VertexBlock& block : blocks) {
    const std::map<std::string, int>& attributes = block.primitive->targets[target];
    const auto position_it = attributes.find("POSITION");
    if (position_it == attributes.end()) {
      Fail(IoErrorKind::kParse, what + " has no POSITION deltas");
    }
    VecData<glm::vec3> positions =
        Accessors().ReadVectors<glm::vec3>(position_it->second, block.vertex_count, true, what);
    VecData<glm::vec3> normals;
    if (with_normals)
      normals = Accessors().ReadVectors<glm::vec3>(attributes.at("NORMAL"), block.vertex_count, true, what);

    // Which vertices the shape moves: the entries a sparse-only accessor lists
    // (kept even when zero, so sparse files round-trip exactly), and the
    // non-zero elements of a dense one (as MakeSparseShape with threshold 0).
    std::vector<std::uint32_t> kept;
    auto add_kept = [&kept, &block](const VecData<glm::vec3>& data) {
      std::vector<std::uint32_t> mine;
      if (data.sparse_only) {
        mine = data.sparse_indices;
      } else {
        for (std::uint32_t v = 0; v < block.vertex_count; ++v) {
          if (data.values[v] != glm::vec3(0.0f)) mine.push_back(v);
        }
      }
      std::vector<std::uint32_t> merged;
      merged.reserve(kept.size() + mine.size());
      std::set_union(kept.begin(), kept.end(), mine.begin(), mine.end(), std::back_inserter(merged));
      kept = std::move(merged);
    };
    add_kept(positions);
    if (with_normals) add_kept(normals);

    auto value_at = [](const VecData<glm::vec3>& data, std::uint32_t v) {
      if (!data.sparse_only) return data.values[v];
      const auto it = std::lower_bound(data.sparse_indices.begin(), data.sparse_indices.end(), v);
      if (it == data.sparse_indices.end() || *it != v) return glm::vec3(0.0f);
      return data.values[static_cast<std::size_t>(it - data.sparse_indices.begin())];
    };
    for (std::uint32_t v : kept) {
      shape.vertex_indices.push_back(block.first_vertex + v);
      shape.position_deltas.push_back(value_at(positions, v));
      if (with_normals) shape.normal_deltas.push_back(value_at(normals, v));
    }
  }
  return shape;
}

// tinygltf's Value::Get(key) asserts that the value is an object; extras may be anything.
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

// Morph targets: glTF requires the same number on every primitive.
void GltfReader::ReadShapes(const tinygltf::Mesh& mesh, const std::vector<VertexBlock>& blocks,
                            RawRig* raw) const {
  const std::size_t target_count = blocks.front().primitive->targets.size();
  bool normal_deltas = target_count > 0;
  for (const VertexBlock& block : blocks) {
    if (block.primitive->targets.size() != target_count) {
      Fail(IoErrorKind::kParse, "primitives have different numbers of morph targets");
    }
    for (const auto& target : block.primitive->targets)
      normal_deltas = normal_deltas && target.count("NORMAL") > 0;
  }
  const tinygltf::Value& target_names = Member(mesh.extras, "targetNames");
  for (std::size_t t = 0; t < target_count; ++t) {
    raw->shapes.push_back(
        ReadShape(blocks, t, StringOr(target_names, t, "target" + std::to_string(t)), normal_deltas));
  }
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

// A file name for image i: its uri's file name, else its name, else "image<i>",
// with the extension of its format.
std::string ImageFileName(const tinygltf::Image& image, std::size_t i, ImageFormat format) {
  std::string stem = image.uri.starts_with("data:") ? std::string() : image.uri;
  stem = stem.substr(stem.find_last_of("/\\") == std::string::npos ? 0 : stem.find_last_of("/\\") + 1);
  if (stem.empty()) stem = image.name;
  stem = stem.substr(0, stem.find_last_of('.'));
  std::erase_if(stem, [](char c) { return c == '/' || c == '\\' || c == '\0'; });
  if (stem.empty() || stem.size() > 100) stem = "image" + std::to_string(i);
  return stem + FileExtension(format);
}

// The images that have bytes (embedded in a bufferView, a data URI, or an
// external file that exists), checked by their header. kept[i] is the index
// of image i in mesh->images, -1 when it has no bytes.
std::vector<std::int32_t> GltfReader::ReadImages(Mesh* mesh) const {
  std::vector<std::int32_t> kept;
  for (std::size_t i = 0; i < model_.images.size(); ++i) {
    const tinygltf::Image& image = model_.images[i];
    const std::string what = "images[" + std::to_string(i) + "]";
    std::span<const std::byte> bytes;
    if (image.bufferView >= 0) {
      bytes = Accessors().ViewBytes(image.bufferView, what);
    } else {
      bytes = {reinterpret_cast<const std::byte*>(image.image.data()), image.image.size()};
    }
    if (bytes.empty()) {
      kept.push_back(-1);  // a missing external file: the material keeps its colour
      continue;
    }
    kept.push_back(static_cast<std::int32_t>(mesh->images.size()));
    EncodedImage encoded = MakeEncodedImage(bytes, std::string(), path_ + ": " + what);  // probes the header
    encoded.name = ImageFileName(image, i, encoded.format);
    mesh->images.push_back(std::move(encoded));
  }
  return kept;
}

void GltfReader::ReadMaterials(Mesh* mesh) const {
  const std::vector<std::int32_t> kept = ReadImages(mesh);
  for (const tinygltf::Material& material : model_.materials) mesh->materials.push_back(ReadMaterial(material, kept));
}

std::int32_t GltfReader::ImageOfTexture(int texture_index, const std::vector<std::int32_t>& kept) const {
  if (texture_index < 0 || texture_index >= static_cast<int>(model_.textures.size())) return -1;
  const int source = model_.textures[static_cast<std::size_t>(texture_index)].source;
  return source >= 0 && source < static_cast<int>(kept.size()) ? kept[static_cast<std::size_t>(source)] : -1;
}

Material GltfReader::ReadMaterial(const tinygltf::Material& material, const std::vector<std::int32_t>& kept) const {
  Material read;
  read.name = material.name;
  const std::vector<double>& colour = material.pbrMetallicRoughness.baseColorFactor;
  if (colour.size() == 4 && std::all_of(colour.begin(), colour.end(), [](double c) { return std::isfinite(c); })) {
    for (int c = 0; c < 4; ++c) read.base_colour[c] = static_cast<float>(colour[static_cast<std::size_t>(c)]);
  }
  read.base_colour_image = ImageOfTexture(material.pbrMetallicRoughness.baseColorTexture.index, kept);
  read.normal_image = ImageOfTexture(material.normalTexture.index, kept);
  const double roughness = material.pbrMetallicRoughness.roughnessFactor;
  if (std::isfinite(roughness)) read.roughness = static_cast<float>(std::clamp(roughness, 0.0, 1.0));
  if (material.alphaMode == "MASK") read.alpha_mode = AlphaMode::kMask;
  if (material.alphaMode == "BLEND") read.alpha_mode = AlphaMode::kBlend;
  if (std::isfinite(material.alphaCutoff)) read.alpha_cutoff = static_cast<float>(material.alphaCutoff);
  read.double_sided = material.doubleSided;
  return read;
}

// The primitive's material; -1 for none, and for one that does not exist (the
// rig reader never required it to).
int GltfReader::MaterialOf(const tinygltf::Primitive& primitive) const {
  return primitive.material < static_cast<int>(model_.materials.size()) ? primitive.material : -1;
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
  return neutral;
}

Mesh GltfReader::ReadMesh() {
  const Neutral neutral = ReadChosenNeutral();
  return NeutralMeshOf(neutral.mesh_index, neutral.raw, neutral.part_primitives);
}

// Whether the scene is one mesh that ReadScene would leave as it is:
// facerig's own, or one that no node transform or skin moves.
bool GltfReader::ReadsAsItIs(const gltf_internal::MeshInstance& only,
                             const std::vector<glm::dmat4>& node_worlds) const {
  if (Member(model_.meshes[static_cast<std::size_t>(only.mesh)].extras, "facerig").IsObject()) return true;
  if (only.skin < 0) return only.world == glm::dmat4(1.0);
  return gltf_internal::SkinPose(model_, only.skin, node_worlds, path_, file_size_).LeavesMeshInPlace();
}

// One mesh of the scene in scene space, its parts named and with materials
// (`default_material` for those without one, noted in *used_default).
RawRig GltfReader::ReadScenePiece(const gltf_internal::MeshInstance& instance,
                                  const std::vector<glm::dmat4>& node_worlds, std::int32_t default_material,
                                  bool* used_default) const {
  const tinygltf::Mesh& mesh = model_.meshes[static_cast<std::size_t>(instance.mesh)];
  const std::string base = mesh.name.empty() ? model_.nodes[static_cast<std::size_t>(instance.node)].name : mesh.name;
  const MeshVertices vertices = GroupMeshVertices(model_, mesh, path_, file_size_);
  RawRig piece;
  std::vector<std::size_t> part_primitives;
  ReadNeutral(mesh, vertices, &piece, &part_primitives);
  ReadShapes(mesh, vertices.blocks, &piece);
  for (std::size_t i = 0; i < piece.parts.size(); ++i) {
    const std::size_t p = part_primitives[i];
    piece.parts[i].name = PartName(model_, mesh, base, p, piece.parts.size());
    const int material = MaterialOf(mesh.primitives[p]);
    piece.parts[i].material = material >= 0 ? material : default_material;
    *used_default = *used_default || material < 0;
  }
  if (instance.skin >= 0) {
    gltf_internal::SkinPose(model_, instance.skin, node_worlds, path_, file_size_).Apply(mesh, vertices, &piece);
  }
  return piece;
}

std::optional<Rig> GltfReader::ReadScene() const {
  const std::vector<gltf_internal::MeshInstance> instances = gltf_internal::SceneMeshInstances(model_);
  if (instances.empty()) return std::nullopt;
  const std::vector<glm::dmat4> node_worlds = gltf_internal::NodeWorlds(model_);
  if (instances.size() == 1 && ReadsAsItIs(instances[0], node_worlds)) return std::nullopt;
  Mesh appearance;
  ReadMaterials(&appearance);
  std::vector<Material> materials = std::move(appearance.materials);
  const auto default_material = static_cast<std::int32_t>(materials.size());
  bool used_default = false;
  gltf_internal::SceneMerger merger;
  for (const gltf_internal::MeshInstance& instance : instances) {
    // A skinned piece is in scene space already: its node transform does not apply.
    merger.Add(ReadScenePiece(instance, node_worlds, default_material, &used_default), instance.world);
  }
  RawRig merged = merger.Finish();
  if (used_default) materials.push_back(Material{.name = "default"});
  merged.materials = std::move(materials);
  merged.images = std::move(appearance.images);
  std::string problem;
  std::optional<Rig> rig = RigBuilder::Build(std::move(merged), &problem);
  if (!rig) Fail(IoErrorKind::kInvalidRig, problem);
  return rig;
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
  ReadFrame(*chosen.mesh, &raw);

  std::string problem;
  std::optional<Rig> rig = RigBuilder::Build(std::move(raw), &problem);
  if (!rig) Fail(IoErrorKind::kInvalidRig, problem);
  return std::move(*rig);
}

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
