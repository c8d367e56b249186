#include "mesh_edges.h"

#include <algorithm>
#include <utility>

namespace facerig {

std::vector<BoundarySide> BoundarySides(std::span<const Triangle> triangles) {
  struct Side {
    std::uint64_t key;  // the two vertices, smaller first
    BoundarySide side;
  };
  std::vector<Side> sides;
  sides.reserve(triangles.size() * 3);
  for (const Triangle& t : triangles) {
    for (std::size_t e = 0; e < 3; ++e) {
      const std::uint32_t a = t[e], b = t[(e + 1) % 3];
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      sides.push_back({key, {a, b, t[(e + 2) % 3]}});
    }
  }
  std::sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) { return x.key < y.key; });
  std::vector<BoundarySide> boundary;
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i;
    while (j < sides.size() && sides[j].key == sides[i].key) ++j;
    if (j - i == 1) boundary.push_back(sides[i].side);
    i = j;
  }
  return boundary;
}

void VertexNeighbours(std::size_t vertex_count, std::span<const Triangle> triangles,
                      std::vector<std::uint32_t>& begin, std::vector<std::uint32_t>& neighbours) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  pairs.reserve(triangles.size() * 6);
  for (const Triangle& t : triangles) {
    for (std::size_t e = 0; e < 3; ++e) {
      pairs.emplace_back(t[e], t[(e + 1) % 3]);
      pairs.emplace_back(t[(e + 1) % 3], t[e]);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  begin.assign(vertex_count + 1, 0);
  for (const auto& [from, to] : pairs) ++begin[from + 1];
  for (std::size_t v = 0; v < vertex_count; ++v) begin[v + 1] += begin[v];
  neighbours.resize(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) neighbours[i] = pairs[i].second;
}

}  // namespace facerig
