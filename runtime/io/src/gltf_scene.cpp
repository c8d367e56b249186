#include "gltf_scene.h"

#include <cmath>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "gltf_scene_transform.h"

namespace facerig::gltf_internal {
namespace {

constexpr int kMaxDepth = 64;

bool AllFinite(const std::vector<double>& values) {
  for (double v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

// The node's matrix (column-major), else translation x rotation x scale;
// malformed values count as absent.
glm::dmat4 LocalTransform(const tinygltf::Node& node) {
  if (node.matrix.size() == 16 && AllFinite(node.matrix)) return glm::make_mat4(node.matrix.data());
  glm::dmat4 local(1.0);
  if (node.translation.size() == 3 && AllFinite(node.translation)) {
    local[3] = glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
  }
  if (node.rotation.size() == 4 && AllFinite(node.rotation)) {
    const glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);  // w, x, y, z
    if (glm::length(q) > 0.0) local = local * glm::mat4_cast(glm::normalize(q));
  }
  if (node.scale.size() == 3 && AllFinite(node.scale)) {
    local = local * glm::scale(glm::dmat4(1.0), glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  }
  return local;
}

}  // namespace

std::vector<MeshInstance> SceneMeshInstances(const tinygltf::Model& model) {
  std::vector<MeshInstance> instances;
  if (model.scenes.empty()) return instances;
  const std::size_t scene = model.defaultScene >= 0 && static_cast<std::size_t>(model.defaultScene) < model.scenes.size()
                                ? static_cast<std::size_t>(model.defaultScene)
                                : 0;
  struct Visit {
    int node;
    glm::dmat4 parent;
    int depth;
  };
  std::vector<Visit> stack;
  for (auto it = model.scenes[scene].nodes.rbegin(); it != model.scenes[scene].nodes.rend(); ++it) {
    stack.push_back({*it, glm::dmat4(1.0), 0});
  }
  std::vector<bool> visited(model.nodes.size(), false);
  while (!stack.empty()) {
    const Visit visit = stack.back();
    stack.pop_back();
    if (visit.node < 0 || static_cast<std::size_t>(visit.node) >= model.nodes.size() || visited[visit.node] ||
        visit.depth > kMaxDepth) {
      continue;
    }
    visited[visit.node] = true;
    const tinygltf::Node& node = model.nodes[static_cast<std::size_t>(visit.node)];
    const glm::dmat4 world = visit.parent * LocalTransform(node);
    if (node.mesh >= 0 && static_cast<std::size_t>(node.mesh) < model.meshes.size()) {
      // glTF ignores a skinned mesh node's transform: its joints place it.
      instances.push_back({node.mesh, visit.node, node.skin >= 0 ? glm::dmat4(1.0) : world, node.skin});
    }
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) {
      stack.push_back({*it, world, visit.depth + 1});
    }
  }
  return instances;
}

std::vector<glm::dmat4> NodeWorlds(const tinygltf::Model& model) {
  const std::size_t count = model.nodes.size();
  std::vector<int> parent(count, -1);
  for (std::size_t n = 0; n < count; ++n) {
    for (int child : model.nodes[n].children) {
      if (child >= 0 && static_cast<std::size_t>(child) < count && parent[child] < 0) {
        parent[child] = static_cast<int>(n);
      }
    }
  }
  std::vector<glm::dmat4> worlds(count, glm::dmat4(1.0));
  std::vector<bool> done(count, false);
  std::vector<int> chain;
  for (std::size_t n = 0; n < count; ++n) {
    // Up to the first node already done (or the root), then down again.
    chain.clear();
    int up = static_cast<int>(n);
    while (up >= 0 && !done[up] && chain.size() <= static_cast<std::size_t>(kMaxDepth)) {
      chain.push_back(up);
      up = parent[up];
    }
    glm::dmat4 world = up >= 0 && done[up] ? worlds[up] : glm::dmat4(1.0);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      if (done[*it]) continue;  // a cycle came back to a node of this chain
      world = world * LocalTransform(model.nodes[static_cast<std::size_t>(*it)]);
      worlds[*it] = world;
      done[*it] = true;
    }
  }
  return worlds;
}

void SceneMerger::Add(RawRig piece, const glm::dmat4& world) {
  if (world != glm::dmat4(1.0)) MoveVertices([&world](std::uint32_t) { return world; }, &piece);
  const auto offset = static_cast<std::uint32_t>(merged_.positions.size());
  const auto triangle_offset = static_cast<std::uint32_t>(merged_.triangles.size());
  all_normals_ = all_normals_ && piece.normals.size() == piece.positions.size();
  all_uvs_ = all_uvs_ && piece.uvs.size() == piece.positions.size();
  piece.normals.resize(piece.positions.size(), glm::vec3(0.0f, 0.0f, 1.0f));
  piece.uvs.resize(piece.positions.size(), glm::vec2(0.0f));
  merged_.positions.insert(merged_.positions.end(), piece.positions.begin(), piece.positions.end());
  merged_.normals.insert(merged_.normals.end(), piece.normals.begin(), piece.normals.end());
  merged_.uvs.insert(merged_.uvs.end(), piece.uvs.begin(), piece.uvs.end());
  for (Triangle t : piece.triangles) merged_.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  for (RawPart part : piece.parts) {
    part.first_triangle += triangle_offset;
    merged_.parts.push_back(std::move(part));
  }
  for (RawBlendShape& shape : piece.shapes) {
    const auto [it, added] = shape_of_name_.try_emplace(shape.name, merged_.shapes.size());
    if (added) {
      merged_.shapes.emplace_back();
      merged_.shapes.back().name = shape.name;
    }
    RawBlendShape& into = merged_.shapes[it->second];
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      into.vertex_indices.push_back(shape.vertex_indices[i] + offset);
      into.position_deltas.push_back(shape.position_deltas[i]);
      if (!shape.normal_deltas.empty()) into.normal_deltas.push_back(shape.normal_deltas[i]);
    }
  }
}

RawRig SceneMerger::Finish() {
  if (!all_normals_) merged_.normals.clear();
  if (!all_uvs_) merged_.uvs.clear();
  bool all_normal_deltas = true;
  for (const RawBlendShape& shape : merged_.shapes) {
    all_normal_deltas = all_normal_deltas && shape.normal_deltas.size() == shape.position_deltas.size();
  }
  if (!all_normal_deltas) {
    for (RawBlendShape& shape : merged_.shapes) shape.normal_deltas.clear();
  }
  merged_.units = Units::kMetres;
  merged_.up_axis = UpAxis::kY;
  return std::move(merged_);
}

}  // namespace facerig::gltf_internal
