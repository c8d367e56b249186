// A skinned mesh where a viewer draws it: at its joints' current node
// transforms, by linear blend skinning. Private to facerig::runtime_io.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <tiny_gltf.h>

#include "facerig/runtime/error.h"
#include "gltf_internal.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig::gltf_internal {

class SkinPose {
 public:
  // Each joint's matrix, jointWorld x inverseBind (a missing
  // inverseBindMatrices is the identity), from `node_worlds` (NodeWorlds).
  // Throws IoError naming `path` and the field for a skin that does not
  // exist, a joint that is not a node, or malformed inverse bind matrices.
  SkinPose(const tinygltf::Model& model, int skin, const std::vector<glm::dmat4>& node_worlds,
           const std::string& path, std::uint64_t file_size);

  // Every joint's matrix is the identity (within float rounding): the mesh
  // is where its vertices say, and reads as it is.
  bool LeavesMeshInPlace() const;

  // Moves `piece` (read from `mesh` as `vertices`) into the pose: each vertex, normal
  // and delta by sum_j w_j * joint matrix j over its JOINTS_n / WEIGHTS_n
  // (weights normalised to sum 1; a vertex without weight follows its first
  // joint). Throws IoError naming the attribute for joints outside the skin,
  // weights that are negative or not finite, and malformed accessors.
  void Apply(const tinygltf::Mesh& mesh, const MeshVertices& vertices, RawRig* piece) const;

 private:
  // What an accessor may hold: JOINTS_n's unsigned integers, WEIGHTS_n's
  // floats or normalized unsigned integers, or floats only.
  enum class Values { kJointIndices, kWeights, kFloats };
  struct Column;
  struct WeightSet;
  struct BlockWeights;
  [[noreturn]] void Fail(IoErrorKind kind, const std::string& message) const;
  Column ReadColumn(int accessor_index, int type, Values values, std::size_t count, const std::string& what) const;
  std::vector<WeightSet> WeightSetsOf(const tinygltf::Primitive& primitive, std::uint32_t vertex_count,
                                      const std::string& what) const;
  glm::dmat4 Blend(const BlockWeights& block, std::uint32_t vertex) const;
  void ReadInverseBinds(int accessor_index, std::vector<glm::dmat4>* inverse_binds) const;

  const tinygltf::Model& model_;
  const std::string& path_;
  std::uint64_t file_size_;
  int skin_;
  std::vector<glm::dmat4> joint_matrices_;
  std::vector<bool> identity_;
};

}  // namespace facerig::gltf_internal
