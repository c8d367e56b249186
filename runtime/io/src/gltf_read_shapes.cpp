// The glTF reader's morph targets: one shape per target, sparse or dense.
#include <algorithm>
#include <iterator>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "gltf_reader.h"

namespace facerig::gltf_internal {

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

}  // namespace facerig::gltf_internal
