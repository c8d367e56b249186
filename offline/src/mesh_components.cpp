#include "facerig/offline/mesh_components.h"

#include <algorithm>
#include <cstdint>

#include <glm/geometric.hpp>

#include "facerig/offline/deformation_transfer.h"

namespace facerig {

std::vector<Triangle> LargePartTriangles(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                                         double min_fraction, std::size_t* left_out) {
  std::vector<std::uint32_t> part_of_vertex;
  const std::size_t parts = ConnectedComponents(positions.size(), triangles, part_of_vertex);
  std::vector<double> area(parts, 0.0);
  for (const Triangle& t : triangles) {
    area[part_of_vertex[t[0]]] +=
        0.5 * glm::length(glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]));
  }
  const double largest = *std::max_element(area.begin(), area.end());
  std::vector<Triangle> kept;
  kept.reserve(triangles.size());
  for (const Triangle& t : triangles) {
    if (area[part_of_vertex[t[0]]] >= min_fraction * largest) kept.push_back(t);
  }
  if (left_out) {
    *left_out = 0;
    std::vector<std::uint8_t> has_triangles(parts, 0);
    for (const Triangle& t : triangles) has_triangles[part_of_vertex[t[0]]] = 1;
    for (std::size_t p = 0; p < parts; ++p) {
      if (has_triangles[p] && area[p] < min_fraction * largest) ++*left_out;
    }
  }
  return kept;
}

}  // namespace facerig
