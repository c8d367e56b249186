// The meshes a glTF scene shows and where: every node of the default scene
// that has a mesh, with its world transform. Private to facerig::runtime_io.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <tiny_gltf.h>

#include "facerig/runtime/rig_builder.h"

namespace facerig::gltf_internal {

struct MeshInstance {
  int mesh = -1;
  int node = -1;
  glm::dmat4 world{1.0};  // node space -> scene space (metres, +Y up)
  int skin = -1;          // the node's skin: its joints place the mesh (SkinPose), not `world`
};

// Depth first from the default scene's roots (scene 0 when none is default);
// a node visited twice (a malformed cycle) or deeper than 64 levels is
// skipped. A skinned mesh's node transform is ignored, as glTF says: its
// joints place it. Empty when the document has no scene.
std::vector<MeshInstance> SceneMeshInstances(const tinygltf::Model& model);

// Every node's world transform (its parents' transforms and its own), whether
// or not it is in the scene: where a skin's joints are. A node in a malformed
// cycle or deeper than the depth limit counts from the identity.
std::vector<glm::dmat4> NodeWorlds(const tinygltf::Model& model);

// One rig from the meshes of a scene, each read in its node's space: moved
// into scene space (MoveVertices) and appended, with shapes of the same
// name merged into one, so that one weight drives every mesh's target.
class SceneMerger {
 public:
  void Add(RawRig piece, const glm::dmat4& world);
  // Normals, UVs and normal deltas are kept only when every piece had them.
  RawRig Finish();

 private:
  RawRig merged_;
  std::map<std::string, std::size_t> shape_of_name_;
  bool all_normals_ = true, all_uvs_ = true;
};

}  // namespace facerig::gltf_internal
