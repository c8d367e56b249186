// Which of the rig's vertices each part's primitive carries in a fresh glTF
// document.
#include <algorithm>
#include <vector>

#include "gltf_internal.h"

namespace facerig::gltf_internal {

std::vector<std::vector<std::uint32_t>> PartVertexSets(const Rig& rig) {
  std::vector<std::vector<std::uint32_t>> sets(rig.parts().size());
  std::vector<bool> used(rig.vertex_count(), false);
  for (std::size_t p = 0; p < sets.size(); ++p) {
    const Part& part = rig.parts()[p];
    std::vector<bool> mine(part.vertex_count, false);
    for (const Triangle& triangle : rig.triangles().subspan(part.first_triangle, part.triangle_count)) {
      for (std::uint32_t v : triangle) {
        mine[v - part.first_vertex] = true;
        used[v] = true;
      }
    }
    for (std::uint32_t i = 0; i < part.vertex_count; ++i) {
      if (mine[i]) sets[p].push_back(part.first_vertex + i);
    }
  }
  // Vertices no triangle uses still belong to the rig: they ride with the first part.
  if (!sets.empty()) {
    std::vector<std::uint32_t>& first = sets.front();
    for (std::uint32_t v = 0; v < used.size(); ++v) {
      if (!used[v]) first.push_back(v);
    }
    std::sort(first.begin(), first.end());
  }
  return sets;
}

}  // namespace facerig::gltf_internal
