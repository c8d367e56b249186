#include "geometry/mesh_edges.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include <glm/geometric.hpp>

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

std::vector<EdgeReach> VerticesWithinReach(std::span<const glm::vec3> positions,
                                           const std::vector<std::uint32_t>& neighbour_begin,
                                           const std::vector<std::uint32_t>& neighbours,
                                           std::span<const std::uint32_t> sources, std::span<const float> reach) {
  std::vector<float> distance(positions.size(), std::numeric_limits<float>::infinity());
  std::vector<std::uint32_t> source_of(positions.size(), 0);
  using Entry = std::pair<float, std::uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  for (std::size_t i = 0; i < sources.size(); ++i) {
    distance[sources[i]] = 0.0f;
    source_of[sources[i]] = static_cast<std::uint32_t>(i);
    queue.emplace(0.0f, sources[i]);
  }
  // Paths longer than the largest reach can keep nothing, so they are not followed.
  const float farthest = reach.empty() ? 0.0f : *std::max_element(reach.begin(), reach.end());
  std::vector<EdgeReach> reached;
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v]) continue;
    if (d < reach[source_of[v]] || d == 0.0f) reached.push_back({v, d, source_of[v]});
    for (std::uint32_t k = neighbour_begin[v]; k < neighbour_begin[v + 1]; ++k) {
      const std::uint32_t w = neighbours[k];
      const float through = d + glm::length(positions[w] - positions[v]);
      if (through < farthest && through < distance[w]) {
        distance[w] = through;
        source_of[w] = source_of[v];
        queue.emplace(through, w);
      }
    }
  }
  return reached;
}

}  // namespace facerig
