#include "gltf_scene_skin.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <span>

#include <glm/gtc/matrix_access.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "gltf_accessors.h"
#include "gltf_components.h"
#include "gltf_scene_transform.h"

namespace facerig::gltf_internal {
namespace {

constexpr int kMaxWeightSets = 8;

// Within float rounding of the identity, relative to the matrix's size.
bool NearIdentity(const glm::dmat4& m) {
  double largest = 1.0, error = 0.0;
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      largest = std::max(largest, std::abs(m[c][r]));
      error = std::max(error, std::abs(m[c][r] - (c == r ? 1.0 : 0.0)));
    }
  }
  return error <= 1e-6 * largest;
}

// The attributes that skin a primitive.
std::map<std::string, int> SkinAttributes(const tinygltf::Primitive& primitive) {
  std::map<std::string, int> skin;
  for (const auto& [name, accessor] : primitive.attributes) {
    if (name.starts_with("JOINTS_") || name.starts_with("WEIGHTS_")) skin.emplace(name, accessor);
  }
  return skin;
}

}  // namespace

// Validated elements of a non-sparse accessor with a bufferView.
struct SkinPose::Column {
  const unsigned char* data = nullptr;
  std::size_t stride = 0;
  int component_type = 0;
  bool normalized = false;
};

struct SkinPose::WeightSet {
  Column joints, weights;
  std::string joints_name, weights_name;  // for errors: "mesh 'Face' JOINTS_0"
};

// One vertex block's first vertex and its weight sets.
struct SkinPose::BlockWeights {
  std::uint32_t first_vertex = 0;
  std::vector<WeightSet> sets;
};

SkinPose::SkinPose(const tinygltf::Model& model, int skin, const std::vector<glm::dmat4>& node_worlds,
                   const std::string& path, std::uint64_t file_size)
    : model_(model), path_(path), file_size_(file_size), skin_(skin) {
  if (skin < 0 || static_cast<std::size_t>(skin) >= model.skins.size()) {
    Fail(IoErrorKind::kIndexOutOfRange, "skin " + std::to_string(skin) + " does not exist (" +
                                            std::to_string(model.skins.size()) + " skins)");
  }
  const tinygltf::Skin& gltf_skin = model.skins[static_cast<std::size_t>(skin)];
  const std::string what = "skins[" + std::to_string(skin) + "]";
  if (gltf_skin.joints.empty()) Fail(IoErrorKind::kParse, what + " has no joints");
  if (gltf_skin.joints.size() > model.nodes.size()) {
    Fail(IoErrorKind::kAbsurdCount, what + " has more joints than the file has nodes");
  }
  std::vector<glm::dmat4> inverse_binds(gltf_skin.joints.size(), glm::dmat4(1.0));
  if (gltf_skin.inverseBindMatrices >= 0) ReadInverseBinds(gltf_skin.inverseBindMatrices, &inverse_binds);
  for (std::size_t j = 0; j < gltf_skin.joints.size(); ++j) {
    const int node = gltf_skin.joints[j];
    if (node < 0 || static_cast<std::size_t>(node) >= node_worlds.size()) {
      Fail(IoErrorKind::kIndexOutOfRange, what + ".joints[" + std::to_string(j) + "]: node " + std::to_string(node) +
                                              " does not exist");
    }
    const glm::dmat4 matrix = node_worlds[static_cast<std::size_t>(node)] * inverse_binds[j];
    identity_.push_back(NearIdentity(matrix));
    joint_matrices_.push_back(identity_.back() ? glm::dmat4(1.0) : matrix);
  }
}

void SkinPose::Fail(IoErrorKind kind, const std::string& message) const { throw IoError(kind, path_, message); }

bool SkinPose::LeavesMeshInPlace() const {
  return std::all_of(identity_.begin(), identity_.end(), [](bool identity) { return identity; });
}

SkinPose::Column SkinPose::ReadColumn(int accessor_index, int type, Values values, std::size_t count,
                                      const std::string& what) const {
  if (accessor_index < 0 || static_cast<std::size_t>(accessor_index) >= model_.accessors.size()) {
    Fail(IoErrorKind::kIndexOutOfRange, what + ": accessor " + std::to_string(accessor_index) + " does not exist");
  }
  const tinygltf::Accessor& accessor = model_.accessors[static_cast<std::size_t>(accessor_index)];
  const int component = accessor.componentType;
  const bool float_type = component == TINYGLTF_COMPONENT_TYPE_FLOAT;
  const bool small_unsigned =
      component == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || component == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  const bool allowed = values == Values::kFloats    ? float_type
                       : values == Values::kWeights ? float_type || (small_unsigned && accessor.normalized)
                                                    : small_unsigned && !accessor.normalized;
  if (accessor.type != type || !allowed) {
    Fail(IoErrorKind::kParse, what + ": accessor " + std::to_string(accessor_index) + " is " +
                                  TypeName(accessor.type) + " of component type " + std::to_string(component) +
                                  (values == Values::kFloats    ? ", expected MAT4 of floats"
                                   : values == Values::kWeights ? ", expected float or normalized unsigned integers"
                                                                : ", expected unsigned byte or short"));
  }
  if (accessor.count < count) {
    Fail(IoErrorKind::kParse, what + ": accessor " + std::to_string(accessor_index) + " has " +
                                  std::to_string(accessor.count) + " elements, expected " + std::to_string(count));
  }
  if (accessor.sparse.isSparse || accessor.bufferView < 0) {
    Fail(IoErrorKind::kParse, what + ": accessor " + std::to_string(accessor_index) +
                                  " is sparse or has no bufferView, which skins do not support");
  }
  const std::span<const std::byte> view = GltfAccessors(path_, model_, file_size_).ViewBytes(accessor.bufferView, what);
  const int components = type == TINYGLTF_TYPE_MAT4 ? 16 : ComponentsOf(type);
  const std::uint64_t element_size = ComponentSize(component) * static_cast<std::uint64_t>(components);
  const std::uint64_t stride_in_view = model_.bufferViews[static_cast<std::size_t>(accessor.bufferView)].byteStride;
  const std::uint64_t stride = stride_in_view != 0 ? stride_in_view : element_size;
  const std::uint64_t offset = accessor.byteOffset;
  // count <= view.size() keeps (count - 1) * stride far from overflowing.
  const bool fits = count == 0 || (count <= view.size() && offset <= view.size() &&
                                   (count - 1) * stride + element_size <= view.size() - offset);
  if (stride < element_size || stride > 252 || !fits) {
    Fail(IoErrorKind::kIndexOutOfRange, what + ": accessor " + std::to_string(accessor_index) +
                                            " runs past the end of its bufferView or has a bad byteStride");
  }
  return {reinterpret_cast<const unsigned char*>(view.data()) + offset, static_cast<std::size_t>(stride), component,
          accessor.normalized};
}

void SkinPose::ReadInverseBinds(int accessor_index, std::vector<glm::dmat4>* inverse_binds) const {
  const std::string what = "skins[" + std::to_string(skin_) + "].inverseBindMatrices";
  const Column column = ReadColumn(accessor_index, TINYGLTF_TYPE_MAT4, Values::kFloats, inverse_binds->size(), what);
  for (std::size_t j = 0; j < inverse_binds->size(); ++j) {
    glm::dmat4& m = (*inverse_binds)[j];
    for (int i = 0; i < 16; ++i) {
      const float value = LoadAsFloat(column.data + j * column.stride + static_cast<std::size_t>(i) * 4,
                                      TINYGLTF_COMPONENT_TYPE_FLOAT, false);
      if (!std::isfinite(value)) {
        Fail(IoErrorKind::kNonFinite, what + ": matrix " + std::to_string(j) + " is not finite");
      }
      glm::value_ptr(m)[i] = value;
    }
    m = glm::row(m, 3, glm::dvec4(0.0, 0.0, 0.0, 1.0));  // affine, as glTF requires
  }
}

// JOINTS_n / WEIGHTS_n for n = 0, 1, ... while both are present.
std::vector<SkinPose::WeightSet> SkinPose::WeightSetsOf(const tinygltf::Primitive& primitive,
                                                       std::uint32_t vertex_count, const std::string& what) const {
  std::vector<WeightSet> sets;
  for (int n = 0; n < kMaxWeightSets; ++n) {
    const std::string joints = "JOINTS_" + std::to_string(n), weights = "WEIGHTS_" + std::to_string(n);
    const auto joints_it = primitive.attributes.find(joints), weights_it = primitive.attributes.find(weights);
    if (joints_it == primitive.attributes.end() || weights_it == primitive.attributes.end()) break;
    const std::string joints_name = what + " " + joints, weights_name = what + " " + weights;
    sets.push_back(
        {ReadColumn(joints_it->second, TINYGLTF_TYPE_VEC4, Values::kJointIndices, vertex_count, joints_name),
         ReadColumn(weights_it->second, TINYGLTF_TYPE_VEC4, Values::kWeights, vertex_count, weights_name),
         joints_name, weights_name});
  }
  if (sets.empty()) Fail(IoErrorKind::kParse, what + " is skinned but has no JOINTS_0 and WEIGHTS_0");
  return sets;
}

glm::dmat4 SkinPose::Blend(const BlockWeights& block, std::uint32_t vertex) const {
  const std::uint32_t v = vertex - block.first_vertex;
  glm::dmat4 sum(0.0);
  double total = 0.0;
  bool all_identity = true;
  std::size_t first_joint = 0;
  for (std::size_t s = 0; s < block.sets.size(); ++s) {
    const WeightSet& set = block.sets[s];
    for (std::size_t k = 0; k < 4; ++k) {
      const std::size_t size = ComponentSize(set.joints.component_type);
      const std::uint32_t joint =
          LoadIndex(set.joints.data + v * set.joints.stride + k * size, set.joints.component_type);
      const std::size_t weight_size = ComponentSize(set.weights.component_type);
      const double weight = LoadAsFloat(set.weights.data + v * set.weights.stride + k * weight_size,
                                        set.weights.component_type, set.weights.normalized);
      if (!std::isfinite(weight) || weight < 0.0) {
        Fail(IoErrorKind::kNonFinite,
             set.weights_name + ": vertex " + std::to_string(v) + " has a negative or non-finite weight");
      }
      if (s == 0 && k == 0) first_joint = joint;
      if (weight == 0.0) continue;
      if (joint >= joint_matrices_.size()) {
        Fail(IoErrorKind::kIndexOutOfRange, set.joints_name + ": vertex " + std::to_string(v) + " names joint " +
                                                std::to_string(joint) + " of a skin of " +
                                                std::to_string(joint_matrices_.size()));
      }
      sum += weight * joint_matrices_[joint];
      total += weight;
      all_identity = all_identity && identity_[joint];
    }
  }
  if (total == 0.0) {
    if (first_joint >= joint_matrices_.size()) {
      Fail(IoErrorKind::kIndexOutOfRange, block.sets.front().joints_name + ": vertex " + std::to_string(v) +
                                              " has no weight and names no joint of the skin");
    }
    return joint_matrices_[first_joint];
  }
  return all_identity ? glm::dmat4(1.0) : sum / total;
}

void SkinPose::Apply(const tinygltf::Mesh& mesh, const MeshVertices& vertices, RawRig* piece) const {
  std::vector<BlockWeights> blocks;
  for (const VertexBlock& block : vertices.blocks) {
    const std::string what = "mesh '" + mesh.name + "'";
    blocks.push_back({block.first_vertex, WeightSetsOf(*block.primitive, block.vertex_count, what)});
  }
  // Primitives that share vertices must share their weights too.
  for (std::size_t p : vertices.triangle_primitives) {
    const tinygltf::Primitive& primitive = mesh.primitives[p];
    const VertexBlock& block = vertices.blocks[vertices.block_of_accessor.at(primitive.attributes.at("POSITION"))];
    if (SkinAttributes(primitive) != SkinAttributes(*block.primitive)) {
      Fail(IoErrorKind::kParse, "mesh '" + mesh.name + "' primitive " + std::to_string(p) +
                                    " shares its POSITION accessor with another but not its JOINTS and WEIGHTS");
    }
  }
  MoveVertices(
      [&](std::uint32_t vertex) {
        const auto after = std::upper_bound(blocks.begin(), blocks.end(), vertex,
                                            [](std::uint32_t v, const BlockWeights& b) { return v < b.first_vertex; });
        return Blend(*(after - 1), vertex);
      },
      piece);
}

}  // namespace facerig::gltf_internal
