// WriteGltf: a rig as a fresh glTF document (one mesh, one node, one scene).
#include "facerig/runtime/io/gltf.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <tiny_gltf.h>

#include "facerig/runtime/error.h"
#include "facerig/runtime/io/gltf_internal.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {
namespace {

constexpr char kGenerator[] = "facerig";

using gltf_internal::AddAccessor;
using gltf_internal::AddMorphTargets;
using gltf_internal::BufferBuilder;
using gltf_internal::FloatAccessor;
using gltf_internal::Format;
using gltf_internal::FormatFromExtension;
using gltf_internal::SetMinMax;
using gltf_internal::StringArray;
using gltf_internal::WithTargetNames;
using gltf_internal::WriteModel;

// POSITION, NORMAL and TEXCOORD_0, shared by every part's primitive.
std::map<std::string, int> AddVertexAttributes(tinygltf::Model* model, BufferBuilder* buffer, const Rig& rig) {
  const std::size_t vertex_count = rig.vertex_count();
  std::map<std::string, int> attributes;
  tinygltf::Accessor positions = FloatAccessor(
      buffer->AddView(rig.positions().data(), rig.positions().size_bytes(), TINYGLTF_TARGET_ARRAY_BUFFER),
      vertex_count, TINYGLTF_TYPE_VEC3);
  SetMinMax(rig.positions(), false, &positions);
  attributes["POSITION"] = AddAccessor(model, std::move(positions));
  attributes["NORMAL"] =
      AddAccessor(model, FloatAccessor(buffer->AddView(rig.normals().data(), rig.normals().size_bytes(),
                                                       TINYGLTF_TARGET_ARRAY_BUFFER),
                                       vertex_count, TINYGLTF_TYPE_VEC3));
  if (!rig.uvs().empty()) {
    // glTF's UV origin is the top-left corner, OBJ's (and the rig's) bottom-left.
    std::vector<glm::vec2> flipped(rig.uvs().begin(), rig.uvs().end());
    for (glm::vec2& uv : flipped) uv.y = 1.0f - uv.y;
    attributes["TEXCOORD_0"] =
        AddAccessor(model, FloatAccessor(buffer->AddView(flipped.data(), flipped.size() * sizeof(glm::vec2),
                                                         TINYGLTF_TARGET_ARRAY_BUFFER),
                                         vertex_count, TINYGLTF_TYPE_VEC2));
  }
  return attributes;
}

// All triangles in one bufferView; each part's accessor is a byte range of it.
struct IndexView {
  int view = -1;
  bool short_indices = false;  // 16-bit, else 32-bit
};

IndexView AddIndexView(BufferBuilder* buffer, const Rig& rig) {
  IndexView index;
  index.short_indices = rig.vertex_count() <= 0xFFFF;  // 0xFFFF is the restart value, never used
  if (index.short_indices) {
    std::vector<std::uint16_t> indices;
    indices.reserve(rig.triangle_count() * 3);
    for (const Triangle& t : rig.triangles()) {
      for (std::uint32_t v : t) indices.push_back(static_cast<std::uint16_t>(v));
    }
    index.view = buffer->AddView(indices.data(), indices.size() * sizeof(std::uint16_t),
                                 TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  } else {
    index.view = buffer->AddView(rig.triangles().data(), rig.triangles().size_bytes(),
                                 TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  }
  return index;
}

// One triangle-list primitive per part, all on the same vertices and targets;
// part_materials: empty, or each part's material (-1: none).
std::vector<tinygltf::Primitive> PartPrimitives(tinygltf::Model* model, const Rig& rig, const IndexView& index,
                                                const std::map<std::string, int>& attributes,
                                                const std::vector<std::map<std::string, int>>& targets,
                                                std::span<const int> part_materials) {
  const std::size_t index_size = index.short_indices ? 2 : 4;
  std::vector<tinygltf::Primitive> primitives;
  for (std::size_t p = 0; p < rig.parts().size(); ++p) {
    const Part& part = rig.parts()[p];
    tinygltf::Accessor indices;
    indices.bufferView = index.view;
    indices.byteOffset = std::size_t{part.first_triangle} * 3 * index_size;
    indices.componentType =
        index.short_indices ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    indices.count = std::size_t{part.triangle_count} * 3;
    indices.type = TINYGLTF_TYPE_SCALAR;
    tinygltf::Primitive primitive;
    primitive.attributes = attributes;
    primitive.indices = AddAccessor(model, std::move(indices));
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    primitive.targets = targets;
    if (!part_materials.empty()) primitive.material = part_materials[p];
    primitives.push_back(std::move(primitive));
  }
  return primitives;
}

// What glTF has no field for: units, up axis and part names in
// extras.facerig, the shape names in extras.targetNames.
tinygltf::Value MeshExtras(const Rig& rig) {
  std::vector<std::string> part_names;
  for (const Part& part : rig.parts()) part_names.push_back(part.name);
  tinygltf::Value::Object facerig;
  facerig["units"] = tinygltf::Value(std::string(ToString(rig.units())));
  facerig["up"] = tinygltf::Value(std::string(rig.up_axis() == UpAxis::kZ ? "Z" : "Y"));
  facerig["parts"] = StringArray(part_names);
  tinygltf::Value::Object extras;
  extras["facerig"] = tinygltf::Value(std::move(facerig));
  tinygltf::Value value(std::move(extras));
  if (rig.shape_count() > 0) value = WithTargetNames(value, rig);
  return value;
}

// One node for mesh 0 whose transform brings the rig's units and up axis to
// glTF's metres and +Y, in the default scene.
void AddSceneNode(tinygltf::Model* model, const Rig& rig, const std::string& name) {
  tinygltf::Node node;
  node.name = name;
  node.mesh = 0;
  const double scale = MetresPerUnit(rig.units());
  if (scale != 1.0) node.scale = {scale, scale, scale};
  if (rig.up_axis() == UpAxis::kZ) {
    // -90 degrees about X: +Z becomes +Y and +Y becomes -Z.
    const double half = std::sqrt(0.5);
    node.rotation = {-half, 0.0, 0.0, half};
  }
  model->nodes.push_back(std::move(node));
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model->scenes.push_back(std::move(scene));
  model->defaultScene = 0;
}

// What a fresh document carries beyond the rig: the materials, and each part's.
struct SurfaceMaterials {
  std::vector<Material> materials;
  std::vector<int> part_materials;  // empty, or one per rig part (-1: none)
};

// An image with this uri (one per distinct uri) and a texture showing it.
int AddTexture(tinygltf::Model* model, const std::string& uri, std::map<std::string, int>* texture_of_uri) {
  const auto [it, added] = texture_of_uri->emplace(uri, static_cast<int>(model->textures.size()));
  if (!added) return it->second;
  tinygltf::Image image;
  image.uri = gltf_internal::SanitizedUtf8(uri);
  model->images.push_back(std::move(image));
  tinygltf::Texture texture;
  texture.source = static_cast<int>(model->images.size()) - 1;
  model->textures.push_back(std::move(texture));
  return it->second;
}

void AddMaterials(tinygltf::Model* model, std::span<const Material> materials) {
  std::map<std::string, int> texture_of_uri;
  for (const Material& material : materials) {
    tinygltf::Material written;
    written.name = gltf_internal::SanitizedUtf8(material.name);
    const glm::vec4& colour = material.base_colour;
    written.pbrMetallicRoughness.baseColorFactor = {colour.r, colour.g, colour.b, colour.a};
    if (!material.base_colour_image.empty()) {
      written.pbrMetallicRoughness.baseColorTexture.index =
          AddTexture(model, material.base_colour_image, &texture_of_uri);
    }
    if (!material.normal_image.empty()) {
      written.normalTexture.index = AddTexture(model, material.normal_image, &texture_of_uri);
    }
    written.alphaMode = material.alpha_mode == AlphaMode::kMask    ? "MASK"
                        : material.alpha_mode == AlphaMode::kBlend ? "BLEND"
                                                                   : "OPAQUE";
    if (material.alpha_mode == AlphaMode::kMask) written.alphaCutoff = material.alpha_cutoff;
    written.doubleSided = material.double_sided;
    model->materials.push_back(std::move(written));
  }
}

tinygltf::Model BuildModel(const Rig& rig, const std::string& name, const SurfaceMaterials& surface = {}) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = kGenerator;
  BufferBuilder buffer(&model);
  const std::map<std::string, int> attributes = AddVertexAttributes(&model, &buffer, rig);
  const std::vector<std::map<std::string, int>> targets = AddMorphTargets(
      &model, &buffer, rig, 0, static_cast<std::uint32_t>(rig.vertex_count()), rig.has_normal_deltas());
  const IndexView index = AddIndexView(&buffer, rig);

  tinygltf::Mesh mesh;
  mesh.name = name;
  mesh.primitives = PartPrimitives(&model, rig, index, attributes, targets, surface.part_materials);
  AddMaterials(&model, surface.materials);
  mesh.extras = MeshExtras(rig);
  if (rig.shape_count() > 0) mesh.weights.assign(rig.shape_count(), 0.0);
  model.meshes.push_back(std::move(mesh));
  AddSceneNode(&model, rig, name);
  return model;
}

// A rig with one vertex per distinct (vertex, corner UV) of `surface`: the
// rig's vertices first, then copies at UV seams with the vertex's normal and
// shape deltas; the parts split into runs of one material (part_materials).
class SeamSplitter {
 public:
  SeamSplitter(const Rig& rig, const Mesh& surface) : rig_(rig), surface_(surface) {}

  RawRig Split(std::vector<int>* part_materials) {
    RawRig raw = RigBuilder::ToRaw(rig_);
    raw.normals.assign(rig_.normals().begin(), rig_.normals().end());  // as they are, not recomputed
    if (!surface_.corner_uvs.empty()) SplitSeams(&raw);
    SplitPartsByMaterial(&raw, part_materials);
    return raw;
  }

 private:
  void SplitSeams(RawRig* raw) {
    raw->uvs = PerVertexAttributes(surface_).uvs;
    std::map<std::tuple<std::uint32_t, float, float>, std::uint32_t> copy_of;  // (vertex, u, v) -> copy
    for (std::size_t t = 0; t < raw->triangles.size(); ++t) {
      for (std::size_t c = 0; c < 3; ++c) {
        const std::uint32_t v = raw->triangles[t][c];
        const glm::vec2 uv = surface_.corner_uvs[t * 3 + c];
        if (uv == raw->uvs[v]) continue;
        const auto [it, added] =
            copy_of.emplace(std::make_tuple(v, uv.x, uv.y), static_cast<std::uint32_t>(raw->positions.size()));
        if (added) {
          copies_.push_back(v);
          raw->positions.push_back(raw->positions[v]);
          raw->normals.push_back(raw->normals[v]);
          raw->uvs.push_back(uv);
        }
        raw->triangles[t][c] = it->second;
      }
    }
    for (RawBlendShape& shape : raw->shapes) AddCopies(&shape);
  }

  // Copies are appended in order after every rig vertex, so the shape's
  // indices stay strictly increasing.
  void AddCopies(RawBlendShape* shape) const {
    const std::vector<std::uint32_t> originals = shape->vertex_indices;  // appending invalidates iterators
    for (std::size_t k = 0; k < copies_.size(); ++k) {
      const auto it = std::lower_bound(originals.begin(), originals.end(), copies_[k]);
      if (it == originals.end() || *it != copies_[k]) continue;
      const auto entry = static_cast<std::size_t>(it - originals.begin());
      shape->vertex_indices.push_back(static_cast<std::uint32_t>(rig_.vertex_count() + k));
      const glm::vec3 position_delta = shape->position_deltas[entry];  // a copy: push_back may reallocate
      shape->position_deltas.push_back(position_delta);
      if (!shape->normal_deltas.empty()) {
        const glm::vec3 normal_delta = shape->normal_deltas[entry];
        shape->normal_deltas.push_back(normal_delta);
      }
    }
  }

  void SplitPartsByMaterial(RawRig* raw, std::vector<int>* part_materials) const {
    if (surface_.triangle_materials.empty()) return;
    std::vector<RawPart> runs;
    for (const RawPart& part : raw->parts) {
      for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count; ++t) {
        const auto material = static_cast<int>(surface_.triangle_materials[t]);
        if (t == part.first_triangle || material != part_materials->back()) {
          runs.push_back({part.name, t, 0});
          part_materials->push_back(material);
        }
        ++runs.back().triangle_count;
      }
    }
    raw->parts = std::move(runs);
  }

  const Rig& rig_;
  const Mesh& surface_;
  std::vector<std::uint32_t> copies_;  // the rig vertex each copy repeats
};

// Whether `surface` lies on the rig: its vertices, and its triangles in the rig's order.
std::optional<std::string> SurfaceMismatch(const Rig& rig, const Mesh& surface) {
  std::string problem;
  if (!surface.Validate(&problem)) return "the surface mesh is invalid: " + problem;
  const auto finite = [](const glm::vec2& uv) { return std::isfinite(uv.x) && std::isfinite(uv.y); };
  if (!std::all_of(surface.corner_uvs.begin(), surface.corner_uvs.end(), finite)) {
    return std::string("the surface mesh has a UV that is not finite");
  }
  if (surface.vertex_count() != rig.vertex_count() ||
      !std::equal(surface.triangles.begin(), surface.triangles.end(), rig.triangles().begin(),
                  rig.triangles().end())) {
    return std::string("the surface mesh's vertices or triangles are not the rig's");
  }
  return std::nullopt;
}

// Whether some corner's UV is not its vertex's UV in the rig.
bool HasSeams(const Rig& rig, const Mesh& surface) {
  if (surface.corner_uvs.empty()) return false;
  if (rig.uvs().empty()) return true;
  for (std::size_t t = 0; t < surface.triangle_count(); ++t) {
    for (std::size_t c = 0; c < 3; ++c) {
      if (surface.corner_uvs[t * 3 + c] != rig.uvs()[surface.triangles[t][c]]) return true;
    }
  }
  return false;
}

}  // namespace

void WriteGltf(const std::filesystem::path& path, const Rig& rig) {
  const Format format = FormatFromExtension(path);
  if (rig.vertex_count() == 0 || rig.triangle_count() == 0) {
    throw IoError(IoErrorKind::kWriteFailed, path.string(), "the rig is empty (no vertices or triangles)");
  }
  gltf_internal::RequireUtf8Names(rig, path.string());
  // The mesh and node are named after the file, whatever bytes its name has.
  WriteModel(path, format, BuildModel(rig, gltf_internal::SanitizedUtf8(path.stem().string())));
}

void WriteGltf(const std::filesystem::path& path, const Rig& rig, const Mesh& surface) {
  if (surface.corner_uvs.empty() && surface.triangle_materials.empty()) return WriteGltf(path, rig);
  const Format format = FormatFromExtension(path);
  if (const std::optional<std::string> problem = SurfaceMismatch(rig, surface)) {
    throw IoError(IoErrorKind::kWriteFailed, path.string(), *problem);
  }
  if (surface.triangle_materials.empty() && !HasSeams(rig, surface)) return WriteGltf(path, rig);
  SurfaceMaterials materials;
  if (!surface.triangle_materials.empty()) materials.materials = surface.materials;
  std::string problem;
  const std::optional<Rig> split =
      RigBuilder::Build(SeamSplitter(rig, surface).Split(&materials.part_materials), &problem);
  if (!split) throw IoError(IoErrorKind::kWriteFailed, path.string(), "the split rig is invalid: " + problem);
  gltf_internal::RequireUtf8Names(*split, path.string());
  WriteModel(path, format, BuildModel(*split, gltf_internal::SanitizedUtf8(path.stem().string()), materials));
}

}  // namespace facerig
