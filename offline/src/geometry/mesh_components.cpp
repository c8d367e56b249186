#include "facerig/offline/geometry/mesh_components.h"

#include <algorithm>
#include <cstdint>
#include <numeric>

#include <glm/geometric.hpp>

#include "facerig/offline/error.h"

namespace facerig {

std::size_t ConnectedComponents(std::size_t vertex_count, std::span<const Triangle> triangles,
                                std::vector<std::uint32_t>& component_of_vertex) {
  std::vector<std::uint32_t> parent(vertex_count);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&parent](std::uint32_t v) {
    while (parent[v] != v) {
      parent[v] = parent[parent[v]];
      v = parent[v];
    }
    return v;
  };
  for (const Triangle& t : triangles) {
    for (int k = 1; k < 3; ++k) {
      const std::uint32_t a = find(t[0]);
      const std::uint32_t b = find(t[static_cast<std::size_t>(k)]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  component_of_vertex.assign(vertex_count, 0);
  std::vector<std::uint32_t> label(vertex_count, UINT32_MAX);
  std::uint32_t count = 0;
  for (std::uint32_t v = 0; v < vertex_count; ++v) {
    const std::uint32_t root = find(v);
    if (label[root] == UINT32_MAX) label[root] = count++;
    component_of_vertex[v] = label[root];
  }
  return count;
}

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
