// WriteGltf: a rig as a fresh glTF document (one mesh, one node, one scene;
// a primitive per part on its own vertices).
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
#include "gltf_internal.h"
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
using gltf_internal::PartVertexSets;
using gltf_internal::SetMinMax;
using gltf_internal::StringArray;
using gltf_internal::WithTargetNames;
using gltf_internal::WriteModel;

// Values of the rig's vertices `vertices`, in that order.
template <typename T>
std::vector<T> Gathered(std::span<const T> values, std::span<const std::uint32_t> vertices) {
  std::vector<T> gathered;
  gathered.reserve(vertices.size());
  for (std::uint32_t v : vertices) gathered.push_back(values[v]);
  return gathered;
}

// POSITION, NORMAL and TEXCOORD_0 of one part's vertices.
std::map<std::string, int> AddVertexAttributes(tinygltf::Model* model, BufferBuilder* buffer, const Rig& rig,
                                               std::span<const std::uint32_t> vertices) {
  const std::size_t count = vertices.size();
  auto add_view = [buffer]<typename T>(const std::vector<T>& values) {
    return buffer->AddView(values.data(), values.size() * sizeof(T), TINYGLTF_TARGET_ARRAY_BUFFER);
  };
  std::map<std::string, int> attributes;
  const std::vector<glm::vec3> positions = Gathered(rig.positions(), vertices);
  tinygltf::Accessor position_accessor = FloatAccessor(add_view(positions), count, TINYGLTF_TYPE_VEC3);
  SetMinMax(positions, false, &position_accessor);
  attributes["POSITION"] = AddAccessor(model, std::move(position_accessor));
  attributes["NORMAL"] =
      AddAccessor(model, FloatAccessor(add_view(Gathered(rig.normals(), vertices)), count, TINYGLTF_TYPE_VEC3));
  if (!rig.uvs().empty()) {
    // glTF's UV origin is the top-left corner, OBJ's (and the rig's) bottom-left.
    std::vector<glm::vec2> flipped = Gathered(rig.uvs(), vertices);
    for (glm::vec2& uv : flipped) uv.y = 1.0f - uv.y;
    attributes["TEXCOORD_0"] = AddAccessor(model, FloatAccessor(add_view(flipped), count, TINYGLTF_TYPE_VEC2));
  }
  return attributes;
}

// An index accessor: 16-bit when every value fits (0xFFFF is the restart
// value, never used), else 32-bit; `target` 0 for data no vertex fetch reads.
int AddIndexAccessor(tinygltf::Model* model, BufferBuilder* buffer, const std::vector<std::uint32_t>& values,
                     std::uint32_t bound, int target) {
  tinygltf::Accessor indices;
  indices.count = values.size();
  indices.type = TINYGLTF_TYPE_SCALAR;
  if (bound <= 0xFFFF) {
    const std::vector<std::uint16_t> shorts(values.begin(), values.end());
    indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    indices.bufferView = buffer->AddView(shorts.data(), shorts.size() * sizeof(std::uint16_t), target);
  } else {
    indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    indices.bufferView = buffer->AddView(values.data(), values.size() * sizeof(std::uint32_t), target);
  }
  return AddAccessor(model, std::move(indices));
}

// A part's triangles as indices into its own vertices.
int AddPartIndices(tinygltf::Model* model, BufferBuilder* buffer, const Rig& rig, const Part& part,
                   std::span<const std::uint32_t> vertices) {
  std::vector<std::uint32_t> local;
  local.reserve(std::size_t{part.triangle_count} * 3);
  for (const Triangle& t : rig.triangles().subspan(part.first_triangle, part.triangle_count)) {
    for (std::uint32_t v : t) {
      local.push_back(static_cast<std::uint32_t>(std::lower_bound(vertices.begin(), vertices.end(), v) -
                                                 vertices.begin()));
    }
  }
  return AddIndexAccessor(model, buffer, local, static_cast<std::uint32_t>(vertices.size()),
                          TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
}

// One triangle-list primitive per part on its own vertices, with morph
// targets for those (all-zero accessors without data for shapes that move
// none of them: glTF wants the same number of targets on every primitive),
// and extras.facerig.vertices: which rig vertex each of its vertices is.
std::vector<tinygltf::Primitive> PartPrimitives(tinygltf::Model* model, BufferBuilder* buffer, const Rig& rig) {
  const std::vector<std::vector<std::uint32_t>> part_vertices = PartVertexSets(rig);
  std::vector<tinygltf::Primitive> primitives;
  for (std::size_t p = 0; p < part_vertices.size(); ++p) {
    const Part& part = rig.parts()[p];
    const std::vector<std::uint32_t>& vertices = part_vertices[p];
    tinygltf::Primitive primitive;
    primitive.attributes = AddVertexAttributes(model, buffer, rig, vertices);
    primitive.indices = AddPartIndices(model, buffer, rig, part, vertices);
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    primitive.targets = AddMorphTargets(model, buffer, rig, vertices, rig.has_normal_deltas());
    primitive.material = part.material;
    tinygltf::Value::Object facerig;
    facerig["vertices"] = tinygltf::Value(
        AddIndexAccessor(model, buffer, vertices, static_cast<std::uint32_t>(rig.vertex_count()), 0));
    tinygltf::Value::Object extras;
    extras["facerig"] = tinygltf::Value(std::move(facerig));
    primitive.extras = tinygltf::Value(std::move(extras));
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
  tinygltf::Mesh mesh;
  mesh.name = name;
  mesh.primitives = PartPrimitives(&model, &buffer, rig);
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
