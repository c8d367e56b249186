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
#include "facerig/runtime/io/output_set.h"
#include "facerig/runtime/rig_builder.h"
#include "facerig/runtime/rig_surface.h"

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

// One triangle-list primitive per part, all on the same vertices and targets.
std::vector<tinygltf::Primitive> PartPrimitives(tinygltf::Model* model, const Rig& rig, const IndexView& index,
                                                const std::map<std::string, int>& attributes,
                                                const std::vector<std::map<std::string, int>>& targets) {
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
    primitive.material = part.material;
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

// The rig's images in the buffer (bufferViews, so a .glb is one file), one
// texture per image.
void AddImages(tinygltf::Model* model, BufferBuilder* buffer, std::span<const EncodedImage> images) {
  for (const EncodedImage& image : images) {
    tinygltf::Image written;
    written.name = gltf_internal::SanitizedUtf8(image.name);
    written.mimeType = MimeType(image.format);
    written.bufferView = buffer->AddView(image.bytes.data(), image.bytes.size(), 0);
    model->images.push_back(std::move(written));
    tinygltf::Texture texture;
    texture.source = static_cast<int>(model->images.size()) - 1;
    model->textures.push_back(std::move(texture));
  }
}

void AddMaterials(tinygltf::Model* model, std::span<const Material> materials) {
  for (const Material& material : materials) {
    tinygltf::Material written;
    written.name = gltf_internal::SanitizedUtf8(material.name);
    const glm::vec4& colour = material.base_colour;
    written.pbrMetallicRoughness.baseColorFactor = {colour.r, colour.g, colour.b, colour.a};
    written.pbrMetallicRoughness.metallicFactor = 0.0;  // skin, eyes and teeth are dielectrics
    written.pbrMetallicRoughness.roughnessFactor = material.roughness;
    written.pbrMetallicRoughness.baseColorTexture.index = material.base_colour_image;  // texture i shows image i
    written.normalTexture.index = material.normal_image;
    written.alphaMode = ToString(material.alpha_mode);
    if (material.alpha_mode == AlphaMode::kMask) written.alphaCutoff = material.alpha_cutoff;
    written.doubleSided = material.double_sided;
    model->materials.push_back(std::move(written));
  }
}

tinygltf::Model BuildModel(const Rig& rig, const std::string& name) {
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
  mesh.primitives = PartPrimitives(&model, rig, index, attributes, targets);
  AddImages(&model, &buffer, rig.images());
  AddMaterials(&model, rig.materials());
  mesh.extras = MeshExtras(rig);
  if (rig.shape_count() > 0) mesh.weights.assign(rig.shape_count(), 0.0);
  model.meshes.push_back(std::move(mesh));
  AddSceneNode(&model, rig, name);
  return model;
}

}  // namespace

void WriteGltf(const std::filesystem::path& path, const Rig& rig) {
  const Format format = FormatFromExtension(path);
  if (rig.vertex_count() == 0 || rig.triangle_count() == 0) {
    throw IoError(IoErrorKind::kWriteFailed, path.string(), "the rig is empty (no vertices or triangles)");
  }
  gltf_internal::RequireUtf8Names(rig, path.string());
  // The mesh and node are named after the file (its final name when this is
  // an output set's temporary), whatever bytes its name has.
  const std::string stem = std::filesystem::path(FinalFileName(path.filename().string())).stem().string();
  WriteModel(path, format, BuildModel(rig, gltf_internal::SanitizedUtf8(stem)));
}

void WriteGltf(const std::filesystem::path& path, const Rig& rig, const Mesh& surface) {
  std::string problem;
  const std::optional<Rig> dressed = RigWithSurface(rig, surface, &problem);
  if (!dressed) throw IoError(IoErrorKind::kWriteFailed, path.string(), problem);
  WriteGltf(path, *dressed);
}

}  // namespace facerig
