#include "openings/rims.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "geometry/mesh_edges.h"
#include "facerig/offline/openings/eyes.h"

namespace facerig {
namespace {

// Distance from rim vertex i to the nearest point of the rim's opposite side
// (its edges between consecutive loop vertices that both face against i), at
// positions + deltas (deltas may be null: at rest); 0 when the rim has none.
// *to_opposite: from vertex i to that point.
float NearestOppositeSide(const OpeningRim& rim, std::size_t i, std::span<const glm::vec3> positions,
                          const std::vector<glm::vec3>* deltas, glm::vec3* to_opposite = nullptr) {
  const auto at = [&](std::uint32_t v) { return deltas ? positions[v] + (*deltas)[v] : positions[v]; };
  const std::size_t size = rim.vertices.size();
  const glm::vec3 into = rim.into_opening[i];
  const glm::vec3 p = at(rim.vertices[i].vertex);
  float best = 0.0f;
  bool found = false;
  for (std::size_t j = 0; j < size; ++j) {
    const std::size_t k = (j + 1) % size;
    if (glm::dot(into, rim.into_opening[j]) > -0.5f || glm::dot(into, rim.into_opening[k]) > -0.5f) continue;
    const glm::vec3 a = at(rim.vertices[j].vertex);
    const glm::vec3 ab = at(rim.vertices[k].vertex) - a;
    const float length2 = glm::dot(ab, ab);
    const float along = length2 > 0.0f ? std::clamp(glm::dot(p - a, ab) / length2, 0.0f, 1.0f) : 0.0f;
    const glm::vec3 q = a + along * ab;
    const float distance = glm::length(q - p);
    if (found && distance >= best) continue;
    found = true;
    best = distance;
    if (to_opposite) *to_opposite = q - p;
  }
  return best;
}

// The target vertices that follow rim's closing: each to its nearest rim
// vertex along mesh edges (rest lengths), within reach times that vertex's
// rest gap, weighted from 1 there to 0 at the limit (smoothstep).
void RimBandOf(OpeningRim& rim, float reach, std::span<const glm::vec3> positions,
               const std::vector<std::uint32_t>& neighbour_begin, const std::vector<std::uint32_t>& neighbours) {
  std::vector<std::uint32_t> sources, rim_index;
  std::vector<float> limits;
  for (std::size_t i = 0; i < rim.vertices.size(); ++i) {
    if (!(rim.rest_gap[i] > 0.0f)) continue;
    sources.push_back(rim.vertices[i].vertex);
    rim_index.push_back(static_cast<std::uint32_t>(i));
    limits.push_back(reach * rim.rest_gap[i]);
  }
  for (const EdgeReach& at : VerticesWithinReach(positions, neighbour_begin, neighbours, sources, limits)) {
    const float t = 1.0f - at.distance / limits[at.source];
    rim.band.push_back({at.vertex, rim_index[at.source], t * t * (3.0f - 2.0f * t)});
  }
}

// A target boundary loop with snapped vertices as a rim: smoothing passes for
// `radius`, same-side neighbours, the opening's direction, rest gaps and,
// when closing is on, the band of vertices that follow it.
OpeningRim RimOfLoop(const std::vector<std::uint32_t>& loop, std::span<const glm::vec3> target_positions,
                               std::span<const glm::vec3> inward,
                               const OpeningParams& params, float radius,
                               const std::vector<std::uint32_t>& neighbour_begin,
                               const std::vector<std::uint32_t>& neighbours) {
  const std::size_t size = loop.size();
  float length = 0.0f;
  for (std::size_t i = 0; i < size; ++i) {
    length += glm::length(target_positions[loop[(i + 1) % size]] - target_positions[loop[i]]);
  }
  // k passes of the (1, 2, 1) / 4 filter: a Gaussian of variance k / 2 vertex spacings squared.
  const float spacing = length / static_cast<float>(size);
  OpeningRim rim;
  const float ratio = spacing > 0.0f ? radius / spacing : 0.0f;
  rim.passes = static_cast<int>(std::lround(std::min(64.0f, 2.0f * ratio * ratio)));
  for (std::size_t i = 0; i < size; ++i) {
    const std::uint32_t v = loop[i];
    const auto same_side = [&](std::size_t j) {
      return static_cast<std::uint32_t>(glm::dot(inward[v], inward[loop[j]]) >= params.rim_min_facing ? j : i);
    };
    rim.vertices.push_back({v, same_side((i + size - 1) % size), same_side((i + 1) % size)});
    rim.into_opening.push_back(-inward[v]);
  }
  rim.rest_gap.resize(size);
  for (std::size_t i = 0; i < size; ++i) {
    rim.rest_gap[i] = NearestOppositeSide(rim, i, target_positions, nullptr);
  }
  if (params.rim_closing_ratio > 0.0f) {
    RimBandOf(rim, params.rim_closing_reach, target_positions, neighbour_begin, neighbours);
  }
  return rim;
}

}  // namespace

std::vector<TemplateRimEdge> TemplateRimEdges(std::span<const Triangle> triangles,
                                              std::span<const MarginDirection> rims) {
  std::vector<TemplateRimEdge> edges;
  if (rims.empty()) return edges;
  const auto rim_of = [&](std::uint32_t v) -> const MarginDirection* {
    const auto it = std::lower_bound(rims.begin(), rims.end(), v,
                                     [](const MarginDirection& r, std::uint32_t x) { return r.vertex < x; });
    return it != rims.end() && it->vertex == v ? &*it : nullptr;
  };
  std::vector<std::uint64_t> seen;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (std::uint8_t e = 0; e < 3; ++e) {
      const auto next = static_cast<std::uint8_t>((e + 1) % 3);
      const std::uint32_t a = triangles[t][e], b = triangles[t][next];
      const MarginDirection* rim_a = rim_of(a);
      const MarginDirection* rim_b = rim_of(b);
      // Both ends opening the same way (not across a lid corner).
      if (!rim_a || !rim_b || glm::dot(rim_a->into_opening, rim_b->into_opening) < 0.5f) continue;
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
      seen.push_back(key);
      const glm::vec3 sum = rim_a->into_opening + rim_b->into_opening;
      const float length = glm::length(sum);
      if (length > 0.0f) edges.push_back({static_cast<std::uint32_t>(t), e, next, sum / length});
    }
  }
  return edges;
}

ClosestPointHit NearestOnRim(glm::vec3 p, glm::vec3 into_opening, std::span<const glm::vec3> fitted,
                             std::span<const Triangle> triangles, std::span<const TemplateRimEdge> edges,
                             float min_facing, float max_distance) {
  ClosestPointHit best;
  best.distance = max_distance;
  for (const TemplateRimEdge& edge : edges) {
    if (glm::dot(edge.into_opening, into_opening) < min_facing) continue;
    const Triangle& t = triangles[edge.triangle];
    const glm::vec3 a = fitted[t[edge.first]], b = fitted[t[edge.second]];
    const glm::vec3 ab = b - a;
    const float length2 = glm::dot(ab, ab);
    const float along = length2 > 0.0f ? std::clamp(glm::dot(p - a, ab) / length2, 0.0f, 1.0f) : 0.0f;
    const glm::vec3 point = a + along * ab;
    const float distance = glm::length(p - point);
    if (distance > best.distance) continue;
    best.triangle = static_cast<std::int32_t>(edge.triangle);
    best.barycentrics = glm::vec3(0.0f);
    best.barycentrics[edge.first] = 1.0f - along;
    best.barycentrics[edge.second] = along;
    best.point = point;
    best.distance = distance;
  }
  return best;
}

void SmoothAlongRim(const OpeningRim& rim, std::vector<glm::vec3>& values, std::vector<glm::vec3>& scratch) {
  scratch.resize(values.size());
  for (int pass = 0; pass < rim.passes; ++pass) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      const RimNeighbours& at = rim.vertices[i];
      scratch[i] = 0.25f * (values[at.previous] + 2.0f * values[i] + values[at.next]);
    }
    values.swap(scratch);
  }
}

void AddSnappedRims(TopologyMapping& mapping, std::span<const glm::vec3> target_positions,
                    std::span<const glm::vec3> inward, std::span<const Triangle> target_triangles, std::span<const std::uint8_t> rim_snapped,
                    const OpeningParams& params, float diagonal) {
  const std::size_t n = target_positions.size();
  mapping.rim_closing_ratio = params.rim_closing_ratio;
  std::vector<std::uint32_t> neighbour_begin, neighbours;
  if (params.rim_closing_ratio > 0.0f) VertexNeighbours(n, target_triangles, neighbour_begin, neighbours);
  const float radius = params.rim_smoothing_radius * diagonal;
  for (const std::vector<std::uint32_t>& loop : BoundaryLoops(target_positions, target_triangles)) {
    if (std::none_of(loop.begin(), loop.end(), [&](std::uint32_t v) { return rim_snapped[v] != 0; })) continue;
    mapping.rims.push_back(RimOfLoop(loop, target_positions, inward, params, radius, neighbour_begin, neighbours));
  }
}

void CloseRims(const TopologyMapping& mapping, std::span<const glm::vec3> target_positions,
               std::vector<glm::vec3>& deltas) {
  const float ratio_limit = mapping.rim_closing_ratio;
  if (!(ratio_limit > 0.0f)) return;
  std::vector<glm::vec3> correction, scratch;
  for (const OpeningRim& rim : mapping.rims) {
    if (rim.band.empty()) continue;
    correction.assign(rim.vertices.size(), glm::vec3(0.0f));
    bool closing = false;
    for (std::size_t i = 0; i < rim.vertices.size(); ++i) {
      if (!(rim.rest_gap[i] > 0.0f)) continue;
      glm::vec3 to_opposite(0.0f);
      const float distance = NearestOppositeSide(rim, i, target_positions, &deltas, &to_opposite);
      // Negative where the side has passed the other (it lies back against its direction into the opening).
      const float gap = glm::dot(to_opposite, rim.into_opening[i]) < 0.0f ? -distance : distance;
      const float ratio = gap / rim.rest_gap[i];
      if (!(ratio < ratio_limit)) continue;
      // Half the way each side (the other side goes its own half); fully from half the limit down.
      const float t = std::clamp((ratio_limit - ratio) / (0.5f * ratio_limit), 0.0f, 1.0f);
      correction[i] = t * t * (3.0f - 2.0f * t) * 0.5f * to_opposite;
      closing = true;
    }
    if (!closing) continue;
    // Smoothed along the rim as the deltas are: the gap left varies vertex to vertex.
    SmoothAlongRim(rim, correction, scratch);
    for (const RimBand& follower : rim.band) {
      deltas[follower.vertex] += follower.weight * correction[follower.rim_index];
    }
  }
}

}  // namespace facerig
