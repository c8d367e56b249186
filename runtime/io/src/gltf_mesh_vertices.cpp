// Which mesh of a glTF document holds the rig, and how its primitives share
// vertices: used by the reader and by facerig::offline's writer into an
// artist's document.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "facerig/runtime/error.h"
#include "gltf_internal.h"

namespace facerig::gltf_internal {

int ChooseMesh(const tinygltf::Model& model) {
  if (model.meshes.empty()) return -1;
  int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (scene < static_cast<int>(model.scenes.size())) {
    std::vector<int> stack(model.scenes[scene].nodes.rbegin(), model.scenes[scene].nodes.rend());
    std::vector<bool> visited(model.nodes.size(), false);  // a malformed file may loop
    while (!stack.empty()) {
      const int index = stack.back();
      stack.pop_back();
      if (index < 0 || index >= static_cast<int>(model.nodes.size()) || visited[index]) continue;
      visited[index] = true;
      const tinygltf::Node& node = model.nodes[index];
      if (node.mesh >= 0 && node.mesh < static_cast<int>(model.meshes.size())) return node.mesh;
      stack.insert(stack.end(), node.children.rbegin(), node.children.rend());
    }
  }
  return 0;
}

MeshVertices GroupMeshVertices(const tinygltf::Model& model, const tinygltf::Mesh& mesh, const std::string& path,
                               std::uint64_t file_size) {
  auto fail = [&path](IoErrorKind kind, const std::string& message) { throw IoError(kind, path, message); };
  MeshVertices vertices;
  std::vector<VertexBlock>& blocks = vertices.blocks;
  for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
    const tinygltf::Primitive& primitive = mesh.primitives[p];
    if (primitive.mode != TINYGLTF_MODE_TRIANGLES) continue;
    const std::string what = "primitive " + std::to_string(p);
    const auto position = primitive.attributes.find("POSITION");
    if (position == primitive.attributes.end()) fail(IoErrorKind::kParse, what + " has no POSITION");
    vertices.triangle_primitives.push_back(p);
    const auto [it, inserted] = vertices.block_of_accessor.emplace(position->second, blocks.size());
    if (!inserted) {
      // Sharing vertices means sharing everything attached to them.
      const tinygltf::Primitive& first = *blocks[it->second].primitive;
      auto attribute = [](const tinygltf::Primitive& q, const char* name) {
        const auto found = q.attributes.find(name);
        return found == q.attributes.end() ? -1 : found->second;
      };
      if (attribute(first, "NORMAL") != attribute(primitive, "NORMAL") ||
          attribute(first, "TEXCOORD_0") != attribute(primitive, "TEXCOORD_0") ||
          first.targets != primitive.targets) {
        fail(IoErrorKind::kParse, what +
                                      " shares its POSITION accessor with another primitive but not its "
                                      "NORMAL, TEXCOORD_0 or morph targets, which a rig cannot represent");
      }
      continue;
    }
    VertexBlock block;
    block.position_accessor = position->second;
    block.primitive = &primitive;
    block.first_vertex = static_cast<std::uint32_t>(vertices.vertex_count);
    if (position->second < 0 || position->second >= static_cast<int>(model.accessors.size())) {
      fail(IoErrorKind::kIndexOutOfRange, what + " POSITION: accessor " + std::to_string(position->second) +
                                              " does not exist (" + std::to_string(model.accessors.size()) +
                                              " accessors)");
    }
    const tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(position->second)];
    if (accessor.bufferView < 0 && accessor.count > file_size) {
      fail(IoErrorKind::kAbsurdCount, what + " POSITION: " + std::to_string(accessor.count) +
                                          " vertices without data in a file of " + std::to_string(file_size) +
                                          " bytes");
    }
    vertices.vertex_count += accessor.count;
    if (vertices.vertex_count > 0xFFFFFFF0u) fail(IoErrorKind::kAbsurdCount, "more than 2^32 vertices");
    block.vertex_count = static_cast<std::uint32_t>(accessor.count);
    blocks.push_back(block);
  }
  if (vertices.triangle_primitives.empty()) {
    fail(IoErrorKind::kEmpty, "the mesh has no triangle-list primitive");
  }
  return vertices;
}

}  // namespace facerig::gltf_internal
