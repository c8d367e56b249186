// The glTF reader's welding: facerig writes each part on its own vertices,
// naming in extras.facerig.vertices which rig vertex each one is; reading
// joins them back into the rig's vertices, in the rig's order.
#include <algorithm>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "gltf_reader.h"

namespace facerig::gltf_internal {

std::vector<std::vector<std::uint32_t>> BlockRigVertices(const tinygltf::Model& model, const MeshVertices& vertices,
                                                         const std::string& path, std::uint64_t file_size) {
  std::vector<std::vector<std::uint32_t>> rig_vertices;
  std::size_t named = 0;
  for (const VertexBlock& block : vertices.blocks) {
    named += Member(Member(block.primitive->extras, "facerig"), "vertices").IsInt() ? 1 : 0;
  }
  if (named == 0) return rig_vertices;
  if (named != vertices.blocks.size()) {
    throw IoError(IoErrorKind::kParse, path, "some primitives have extras.facerig.vertices and others not");
  }
  const GltfAccessors accessors(path, model, file_size);
  for (const VertexBlock& block : vertices.blocks) {
    const int accessor = Member(Member(block.primitive->extras, "facerig"), "vertices").Get<int>();
    rig_vertices.push_back(accessors.ReadIntegers(accessor, block.vertex_count, vertices.vertex_count,
                                                  "extras.facerig.vertices (accessor " + std::to_string(accessor) +
                                                      ")"));
  }
  return rig_vertices;
}

std::vector<std::uint32_t> GltfReader::ReadRigVertices(const MeshVertices& vertices) const {
  std::vector<std::uint32_t> rig_vertex;
  for (const std::vector<std::uint32_t>& block : BlockRigVertices(model_, vertices, path_, file_size_)) {
    rig_vertex.insert(rig_vertex.end(), block.begin(), block.end());
  }
  return rig_vertex;
}

void GltfReader::WeldNeutral(const std::vector<std::uint32_t>& rig_vertex, RawRig* raw) const {
  const std::size_t count = *std::max_element(rig_vertex.begin(), rig_vertex.end()) + std::size_t{1};
  std::vector<bool> seen(count, false);
  std::vector<glm::vec3> positions(count), normals(raw->normals.empty() ? 0 : count);
  std::vector<glm::vec2> uvs(raw->uvs.empty() ? 0 : count);
  for (std::size_t i = 0; i < rig_vertex.size(); ++i) {
    const std::uint32_t v = rig_vertex[i];
    if (seen[v]) continue;  // a vertex parts share: the same values in each
    seen[v] = true;
    positions[v] = raw->positions[i];
    if (!normals.empty()) normals[v] = raw->normals[i];
    if (!uvs.empty()) uvs[v] = raw->uvs[i];
  }
  const auto missing = std::find(seen.begin(), seen.end(), false);
  if (missing != seen.end()) {
    Fail(IoErrorKind::kParse, "extras.facerig.vertices: no primitive has vertex " +
                                  std::to_string(missing - seen.begin()) + " of " + std::to_string(count));
  }
  raw->positions = std::move(positions);
  raw->normals = std::move(normals);
  raw->uvs = std::move(uvs);
  for (Triangle& triangle : raw->triangles) {
    for (std::uint32_t& v : triangle) v = rig_vertex[v];
  }
}

void GltfReader::WeldShapes(const std::vector<std::uint32_t>& rig_vertex, RawRig* raw) const {
  std::vector<std::size_t> order;
  for (RawBlendShape& shape : raw->shapes) {
    order.resize(shape.vertex_indices.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return rig_vertex[shape.vertex_indices[a]] < rig_vertex[shape.vertex_indices[b]];
    });
    RawBlendShape welded;
    welded.name = std::move(shape.name);
    for (std::size_t i : order) {
      const std::uint32_t v = rig_vertex[shape.vertex_indices[i]];
      if (!welded.vertex_indices.empty() && welded.vertex_indices.back() == v) continue;
      welded.vertex_indices.push_back(v);
      welded.position_deltas.push_back(shape.position_deltas[i]);
      if (!shape.normal_deltas.empty()) welded.normal_deltas.push_back(shape.normal_deltas[i]);
    }
    shape = std::move(welded);
  }
}

}  // namespace facerig::gltf_internal
