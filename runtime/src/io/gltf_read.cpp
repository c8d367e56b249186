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
#include "gltf_components.h"

namespace facerig {
namespace {

using gltf_internal::ChooseMesh;
using gltf_internal::ComponentSize;
using gltf_internal::ComponentsOf;
using gltf_internal::Format;
using gltf_internal::FormatFromExtension;
using gltf_internal::GroupMeshVertices;
using gltf_internal::IsIndexType;
using gltf_internal::LoadAsFloat;
using gltf_internal::LoadIndex;
using gltf_internal::MeshVertices;
using gltf_internal::ParseModel;
using gltf_internal::TypeName;
using gltf_internal::VertexBlock;

// One vec2/vec3 accessor as read. Dense: `values` has count elements. An
// accessor without a bufferView is zero except its sparse entries; when asked,
// those are kept as they are (`sparse_only`) instead of being expanded.
template <typename Vec>
struct VecData {
  std::vector<Vec> values;
  bool sparse_only = false;
  std::vector<std::uint32_t> sparse_indices;  // sparse_only: strictly increasing
};

// Where a run of elements lies: a validated pointer and the stride between them.
struct Elements {
  const unsigned char* data = nullptr;
  std::size_t stride = 0;
};

class GltfReader {
 public:
  GltfReader(std::string path, tinygltf::Model model, std::uint64_t file_size)
      : path_(std::move(path)), model_(std::move(model)), file_size_(file_size) {}

  // The rig, and the neutral as a Mesh into *mesh when not null.
  Rig Read(Mesh* mesh);
  Mesh ReadMesh();

 private:
  [[noreturn]] void Fail(IoErrorKind kind, const std::string& message) const {
    throw IoError(kind, path_, message);
  }

  const tinygltf::Accessor& GetAccessor(int index, const std::string& what) const;
  Elements ViewElements(int view_index, std::uint64_t byte_offset, std::uint64_t count,
                        std::uint64_t element_size, bool allow_stride, const std::string& what) const;
  const tinygltf::Accessor& GetVectorAccessor(int accessor_index, int components,
                                              std::optional<std::size_t> expected_count,
                                              const std::string& what) const;
  template <typename Vec>
  VecData<Vec> ReadVectors(int accessor_index, std::optional<std::size_t> expected_count, bool keep_sparse,
                           const std::string& what) const;
  std::vector<std::uint32_t> ReadIndices(const tinygltf::Primitive& primitive, const VertexBlock& block,
                                         const std::string& what) const;
  std::vector<std::uint32_t> ReadSparseIndices(const tinygltf::Accessor& accessor,
                                               const std::string& what) const;
  RawBlendShape ReadShape(const std::vector<VertexBlock>& blocks, std::size_t target, std::string name,
                          bool with_normals) const;
  void ReadVertices(const std::vector<VertexBlock>& blocks, RawRig* raw) const;
  void ReadParts(const tinygltf::Mesh& mesh, const MeshVertices& vertices, RawRig* raw,
                 std::vector<std::size_t>* part_primitives) const;
  void ReadNeutral(const tinygltf::Mesh& mesh, const MeshVertices& vertices, RawRig* raw,
                   std::vector<std::size_t>* part_primitives) const;
  Mesh NeutralMeshOf(int mesh_index, const RawRig& raw, const std::vector<std::size_t>& part_primitives) const;
  std::string ImageUri(int texture_index) const;
  Material ReadMaterial(const tinygltf::Material& material) const;
  int MaterialOf(const tinygltf::Primitive& primitive) const;
  int ChosenMesh() const;
  void ReadShapes(const tinygltf::Mesh& mesh, const std::vector<VertexBlock>& blocks, RawRig* raw) const;
  void ReadFrame(const tinygltf::Mesh& mesh, RawRig* raw) const;

  std::string path_;
  tinygltf::Model model_;
  std::uint64_t file_size_;
};

const tinygltf::Accessor& GltfReader::GetAccessor(int index, const std::string& what) const {
  if (index < 0 || index >= static_cast<int>(model_.accessors.size())) {
    Fail(IoErrorKind::kIndexOutOfRange, what + ": accessor " + std::to_string(index) + " does not exist (" +
                                            std::to_string(model_.accessors.size()) + " accessors)");
  }
  return model_.accessors[index];
}

Elements GltfReader::ViewElements(int view_index, std::uint64_t byte_offset, std::uint64_t count,
                                  std::uint64_t element_size, bool allow_stride,
                                  const std::string& what) const {
  if (view_index < 0 || view_index >= static_cast<int>(model_.bufferViews.size())) {
    Fail(IoErrorKind::kIndexOutOfRange,
         what + ": bufferView " + std::to_string(view_index) + " does not exist");
  }
  const tinygltf::BufferView& view = model_.bufferViews[view_index];
  if (view.buffer < 0 || view.buffer >= static_cast<int>(model_.buffers.size())) {
    Fail(IoErrorKind::kIndexOutOfRange, what + ": bufferView " + std::to_string(view_index) +
                                            " names buffer " + std::to_string(view.buffer) +
                                            ", which does not exist");
  }
  const std::vector<unsigned char>& buffer = model_.buffers[view.buffer].data;
  if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset) {
    Fail(IoErrorKind::kIndexOutOfRange,
         what + ": bufferView " + std::to_string(view_index) + " (bytes " + std::to_string(view.byteOffset) +
             " + " + std::to_string(view.byteLength) + ") lies outside its buffer of " +
             std::to_string(buffer.size()) + " bytes");
  }
  // Checked before anything is allocated from `count`: a count whose elements
  // could not fit in the whole buffer is absurd, not merely out of range.
  if (count > buffer.size() / element_size) {
    Fail(IoErrorKind::kAbsurdCount, what + ": " + std::to_string(count) + " elements of " +
                                        std::to_string(element_size) + " bytes cannot fit in a buffer of " +
                                        std::to_string(buffer.size()) + " bytes");
  }
  std::uint64_t stride = element_size;
  if (allow_stride && view.byteStride != 0) {
    if (view.byteStride < element_size || view.byteStride > 252) {
      Fail(IoErrorKind::kParse, what + ": byteStride " + std::to_string(view.byteStride) +
                                    " is invalid for elements of " + std::to_string(element_size) + " bytes");
    }
    stride = view.byteStride;
  }
  if (count > 0 && (byte_offset > view.byteLength ||
                    (count - 1) * stride + element_size > view.byteLength - byte_offset)) {
    Fail(IoErrorKind::kIndexOutOfRange, what + ": " + std::to_string(count) + " elements at offset " +
                                            std::to_string(byte_offset) + " run past the end of bufferView " +
                                            std::to_string(view_index) + " (" +
                                            std::to_string(view.byteLength) + " bytes)");
  }
  return {buffer.data() + view.byteOffset + byte_offset, static_cast<std::size_t>(stride)};
}

std::vector<std::uint32_t> GltfReader::ReadSparseIndices(const tinygltf::Accessor& accessor,
                                                         const std::string& what) const {
  const auto& sparse = accessor.sparse;
  if (sparse.count < 0) Fail(IoErrorKind::kParse, what + ": negative sparse count");
  if (static_cast<std::uint64_t>(sparse.count) > accessor.count) {
    Fail(IoErrorKind::kAbsurdCount, what + ": sparse count " + std::to_string(sparse.count) +
                                        " exceeds the accessor's count " + std::to_string(accessor.count));
  }
  if (!IsIndexType(sparse.indices.componentType)) {
    Fail(IoErrorKind::kParse, what + ": sparse indices must be UNSIGNED_BYTE, _SHORT or _INT");
  }
  if (sparse.indices.byteOffset < 0)
    Fail(IoErrorKind::kIndexOutOfRange, what + ": negative sparse byteOffset");
  const std::size_t index_size = ComponentSize(sparse.indices.componentType);
  const Elements elements =
      ViewElements(sparse.indices.bufferView, static_cast<std::uint64_t>(sparse.indices.byteOffset),
                   static_cast<std::uint64_t>(sparse.count), index_size, false, what + " sparse indices");
  std::vector<std::uint32_t> indices(static_cast<std::size_t>(sparse.count));
  for (std::size_t i = 0; i < indices.size(); ++i) {
    indices[i] = LoadIndex(elements.data + i * elements.stride, sparse.indices.componentType);
    if (indices[i] >= accessor.count) {
      Fail(IoErrorKind::kIndexOutOfRange, what + ": sparse index " + std::to_string(indices[i]) +
                                              " >= count " + std::to_string(accessor.count));
    }
    if (i > 0 && indices[i] <= indices[i - 1]) {
      Fail(IoErrorKind::kParse, what + ": sparse indices are not strictly increasing");
    }
  }
  return indices;
}

// A float (or small normalized integer) accessor of `components` components
// and, when given, `expected_count` elements.
const tinygltf::Accessor& GltfReader::GetVectorAccessor(int accessor_index, int components,
                                                        std::optional<std::size_t> expected_count,
                                                        const std::string& what) const {
  const tinygltf::Accessor& accessor = GetAccessor(accessor_index, what);
  if (ComponentsOf(accessor.type) != components) {
    Fail(IoErrorKind::kParse, what + ": accessor " + std::to_string(accessor_index) + " is " +
                                  TypeName(accessor.type) + ", expected VEC" + std::to_string(components));
  }
  const int component_type = accessor.componentType;
  const std::size_t component_size = ComponentSize(component_type);
  if (component_type != TINYGLTF_COMPONENT_TYPE_FLOAT && (component_size == 0 || component_size > 2)) {
    Fail(IoErrorKind::kParse, what + ": accessor " + std::to_string(accessor_index) +
                                  " has an unsupported component type " + std::to_string(component_type));
  }
  if (expected_count && accessor.count != *expected_count) {
    Fail(IoErrorKind::kParse, what + ": accessor " + std::to_string(accessor_index) + " has " +
                                  std::to_string(accessor.count) + " elements, expected " +
                                  std::to_string(*expected_count));
  }
  // Elements without data (no bufferView) cost memory but no file bytes, so a
  // tiny file must not be able to ask for billions of them.
  if (accessor.bufferView < 0 && accessor.count > file_size_) {
    Fail(IoErrorKind::kAbsurdCount, what + ": accessor " + std::to_string(accessor_index) + " declares " +
                                        std::to_string(accessor.count) +
                                        " elements without data in a file of " + std::to_string(file_size_) +
                                        " bytes");
  }
  return accessor;
}

template <typename Vec>
VecData<Vec> GltfReader::ReadVectors(int accessor_index, std::optional<std::size_t> expected_count,
                                     bool keep_sparse, const std::string& what) const {
  constexpr int kComponents = static_cast<int>(Vec::length());
  const tinygltf::Accessor& accessor = GetVectorAccessor(accessor_index, kComponents, expected_count, what);
  const int component_type = accessor.componentType;
  const std::size_t component_size = ComponentSize(component_type);
  const std::size_t element_size = component_size * kComponents;
  auto load = [&](const unsigned char* p, std::size_t element) {
    Vec v;
    for (int c = 0; c < kComponents; ++c) {
      v[c] =
          LoadAsFloat(p + static_cast<std::size_t>(c) * component_size, component_type, accessor.normalized);
      if (!std::isfinite(v[c])) {
        Fail(IoErrorKind::kNonFinite, what + ": element " + std::to_string(element) + " of accessor " +
                                          std::to_string(accessor_index) + " is not finite");
      }
    }
    return v;
  };

  VecData<Vec> result;
  if (accessor.bufferView >= 0) {
    const Elements elements =
        ViewElements(accessor.bufferView, accessor.byteOffset, accessor.count, element_size, true, what);
    result.values.resize(accessor.count);
    for (std::size_t i = 0; i < accessor.count; ++i)
      result.values[i] = load(elements.data + i * elements.stride, i);
  }
  if (!accessor.sparse.isSparse) {
    if (accessor.bufferView < 0) result.values.assign(accessor.count, Vec(0.0f));
    return result;
  }
  const std::vector<std::uint32_t> indices = ReadSparseIndices(accessor, what);
  if (accessor.sparse.values.byteOffset < 0) {
    Fail(IoErrorKind::kIndexOutOfRange, what + ": negative sparse byteOffset");
  }
  const Elements values = ViewElements(accessor.sparse.values.bufferView,
                                       static_cast<std::uint64_t>(accessor.sparse.values.byteOffset),
                                       indices.size(), element_size, false, what + " sparse values");
  if (accessor.bufferView < 0 && keep_sparse) {
    result.sparse_only = true;
    result.values.resize(indices.size());
    for (std::size_t i = 0; i < indices.size(); ++i)
      result.values[i] = load(values.data + i * values.stride, indices[i]);
    result.sparse_indices = indices;
    return result;
  }
  if (accessor.bufferView < 0) result.values.assign(accessor.count, Vec(0.0f));
  for (std::size_t i = 0; i < indices.size(); ++i) {
    result.values[indices[i]] = load(values.data + i * values.stride, indices[i]);
  }
  return result;
}

std::vector<std::uint32_t> GltfReader::ReadIndices(const tinygltf::Primitive& primitive,
                                                   const VertexBlock& block, const std::string& what) const {
  std::vector<std::uint32_t> indices;
  if (primitive.indices < 0) {
    // Not indexed: consecutive vertices form the triangles.
    indices.resize(block.vertex_count);
    for (std::uint32_t i = 0; i < block.vertex_count; ++i) indices[i] = block.first_vertex + i;
  } else {
    const tinygltf::Accessor& accessor = GetAccessor(primitive.indices, what);
    if (accessor.type != TINYGLTF_TYPE_SCALAR || !IsIndexType(accessor.componentType)) {
      Fail(IoErrorKind::kParse, what + ": indices must be SCALAR UNSIGNED_BYTE, _SHORT or _INT");
    }
    if (accessor.bufferView < 0) Fail(IoErrorKind::kParse, what + ": the indices accessor has no bufferView");
    if (accessor.sparse.isSparse) Fail(IoErrorKind::kParse, what + ": sparse indices are not supported");
    const Elements elements = ViewElements(accessor.bufferView, accessor.byteOffset, accessor.count,
                                           ComponentSize(accessor.componentType), false, what + " indices");
    indices.resize(accessor.count);
    for (std::size_t i = 0; i < accessor.count; ++i) {
      const std::uint32_t index = LoadIndex(elements.data + i * elements.stride, accessor.componentType);
      if (index >= block.vertex_count) {
        Fail(IoErrorKind::kIndexOutOfRange, what + ": index " + std::to_string(i) + " is " +
                                                std::to_string(index) + ", but POSITION has " +
                                                std::to_string(block.vertex_count) + " vertices");
      }
      indices[i] = block.first_vertex + index;
    }
  }
  if (indices.size() % 3 != 0) {
    Fail(IoErrorKind::kParse,
         what + ": " + std::to_string(indices.size()) + " indices is not a whole number of triangles");
  }
  return indices;
}

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
        ReadVectors<glm::vec3>(position_it->second, block.vertex_count, true, what);
    VecData<glm::vec3> normals;
    if (with_normals)
      normals = ReadVectors<glm::vec3>(attributes.at("NORMAL"), block.vertex_count, true, what);

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
  for (const VertexBlock& block : blocks) {
    const std::string what = "accessor " + std::to_string(block.position_accessor) + " (POSITION)";
    VecData<glm::vec3> positions = ReadVectors<glm::vec3>(block.position_accessor, std::nullopt, false, what);
    raw->positions.insert(raw->positions.end(), positions.values.begin(), positions.values.end());
    if (all_normals) {
      VecData<glm::vec3> normals = ReadVectors<glm::vec3>(block.primitive->attributes.at("NORMAL"),
                                                          block.vertex_count, false, "NORMAL");
      raw->normals.insert(raw->normals.end(), normals.values.begin(), normals.values.end());
    }
    if (all_uvs) {
      VecData<glm::vec2> uvs = ReadVectors<glm::vec2>(block.primitive->attributes.at("TEXCOORD_0"),
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
    const std::vector<std::uint32_t> indices = ReadIndices(primitive, block, what);
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

// The uri of the external image a texture shows; empty for an image in a
// bufferView or a data URI (no file to name), or a dangling index.
std::string GltfReader::ImageUri(int texture_index) const {
  if (texture_index < 0 || texture_index >= static_cast<int>(model_.textures.size())) return {};
  const int source = model_.textures[static_cast<std::size_t>(texture_index)].source;
  if (source < 0 || source >= static_cast<int>(model_.images.size())) return {};
  const std::string& uri = model_.images[static_cast<std::size_t>(source)].uri;
  return uri.starts_with("data:") ? std::string() : uri;
}

Material GltfReader::ReadMaterial(const tinygltf::Material& material) const {
  Material read;
  read.name = material.name;
  const std::vector<double>& colour = material.pbrMetallicRoughness.baseColorFactor;
  if (colour.size() == 4 && std::all_of(colour.begin(), colour.end(), [](double c) { return std::isfinite(c); })) {
    for (int c = 0; c < 4; ++c) read.base_colour[c] = static_cast<float>(colour[static_cast<std::size_t>(c)]);
  }
  read.base_colour_image = ImageUri(material.pbrMetallicRoughness.baseColorTexture.index);
  read.normal_image = ImageUri(material.normalTexture.index);
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

// The neutral read into `raw` as a Mesh, with part names from the mesh's (or
// its node's) name where extras.facerig.parts has none, and the materials.
Mesh GltfReader::NeutralMeshOf(int mesh_index, const RawRig& raw,
                               const std::vector<std::size_t>& part_primitives) const {
  const tinygltf::Mesh& gltf_mesh = model_.meshes[static_cast<std::size_t>(mesh_index)];
  std::string base = gltf_mesh.name;
  for (std::size_t n = 0; base.empty() && n < model_.nodes.size(); ++n) {
    if (model_.nodes[n].mesh == mesh_index) base = model_.nodes[n].name;
  }
  const tinygltf::Value& part_names = Member(Member(gltf_mesh.extras, "facerig"), "parts");
  Mesh mesh = NeutralMesh(raw);
  bool any_material = false, any_without = false;
  for (std::size_t i = 0; i < part_primitives.size(); ++i) {
    const std::size_t p = part_primitives[i];
    const std::string fallback = base.empty()              ? "primitive" + std::to_string(p)
                                 : part_primitives.size() == 1 ? base
                                                               : base + ".primitive" + std::to_string(p);
    mesh.part_names[i] = StringOr(part_names, p, fallback);
    (MaterialOf(gltf_mesh.primitives[p]) >= 0 ? any_material : any_without) = true;
  }
  for (const tinygltf::Material& material : model_.materials) mesh.materials.push_back(ReadMaterial(material));
  if (!any_material) return mesh;
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

Mesh GltfReader::ReadMesh() {
  const int mesh_index = ChosenMesh();
  const tinygltf::Mesh& mesh = model_.meshes[static_cast<std::size_t>(mesh_index)];
  const MeshVertices vertices = GroupMeshVertices(model_, mesh, path_, file_size_);
  RawRig raw;
  std::vector<std::size_t> part_primitives;
  ReadNeutral(mesh, vertices, &raw, &part_primitives);
  return NeutralMeshOf(mesh_index, raw, part_primitives);
}

Rig GltfReader::Read(Mesh* neutral) {
  const int mesh_index = ChosenMesh();
  const tinygltf::Mesh& mesh = model_.meshes[static_cast<std::size_t>(mesh_index)];
  const MeshVertices vertices = GroupMeshVertices(model_, mesh, path_, file_size_);

  RawRig raw;
  std::vector<std::size_t> part_primitives;
  ReadNeutral(mesh, vertices, &raw, &part_primitives);
  if (neutral) *neutral = NeutralMeshOf(mesh_index, raw, part_primitives);
  ReadShapes(mesh, vertices.blocks, &raw);
  ReadFrame(mesh, &raw);

  std::string problem;
  std::optional<Rig> rig = RigBuilder::Build(std::move(raw), &problem);
  if (!rig) Fail(IoErrorKind::kInvalidRig, problem);
  return std::move(*rig);
}

GltfReader ReaderOfFile(const std::filesystem::path& path) {
  const Format format = FormatFromExtension(path);
  std::uint64_t file_size = 0;
  tinygltf::Model model = ParseModel(path, format, &file_size);
  gltf_internal::RefuseCompression(model, path.string());
  return GltfReader(path.string(), std::move(model), file_size);
}

GltfReader ReaderOfBytes(std::span<const std::byte> bytes, const std::filesystem::path& path) {
  const Format format = FormatFromExtension(path);
  tinygltf::Model model = gltf_internal::ParseModelBytes(
      {reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()}, path, format);
  gltf_internal::RefuseCompression(model, path.string());
  return GltfReader(path.string(), std::move(model), bytes.size());
}

}  // namespace

Rig ReadGltf(const std::filesystem::path& path) { return ReaderOfFile(path).Read(nullptr); }

Rig ReadGltf(const std::filesystem::path& path, Mesh* mesh) { return ReaderOfFile(path).Read(mesh); }

Rig ParseGltf(std::span<const std::byte> bytes, const std::filesystem::path& path) {
  return ReaderOfBytes(bytes, path).Read(nullptr);
}

Mesh ReadGltfMesh(const std::filesystem::path& path) { return ReaderOfFile(path).ReadMesh(); }

Mesh ParseGltfMesh(std::span<const std::byte> bytes, const std::filesystem::path& path) {
  return ReaderOfBytes(bytes, path).ReadMesh();
}

}  // namespace facerig
