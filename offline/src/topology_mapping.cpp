#include "facerig/offline/topology_mapping.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <limits>
#include <memory>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/closest_point.h"
#include "facerig/offline/deformation_transfer.h"
#include "facerig/offline/registration_error.h"
#include "eye_openings.h"
#include "mesh_edges.h"

namespace facerig {
namespace {

void CheckTarget(std::span<const glm::vec3> positions, std::span<const Triangle> triangles) {
  if (positions.empty() || triangles.empty()) {
    throw InvalidInputError("topology mapping: the target mesh is empty");
  }
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const glm::vec3 p = positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw InvalidInputError("topology mapping: target vertex " + std::to_string(v) +
                              " has a non-finite coordinate");
    }
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (std::uint32_t v : triangles[t]) {
      if (v >= positions.size()) {
        throw InvalidInputError("topology mapping: target triangle " + std::to_string(t) + " uses vertex " +
                                std::to_string(v) + " of " + std::to_string(positions.size()));
      }
    }
  }
}

float BoundingDiagonalOf(std::span<const glm::vec3> positions) {
  glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (const glm::vec3& p : positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return glm::length(hi - lo);
}

// 1 at distance <= full, 0 at >= zero, smoothstep between.
float Falloff(float distance, float full, float zero) {
  if (distance <= full) return 1.0f;
  if (distance >= zero) return 0.0f;
  const float t = (distance - full) / (zero - full);
  return 1.0f - t * t * (3.0f - 2.0f * t);
}

// The fitted template restricted to some of its connected parts, with the
// map from the subset's triangle index back to the template's.
struct PartSurface {
  std::unique_ptr<ClosestPointQuery> query;
  std::vector<std::uint32_t> template_triangle;
};

// Vertices on the mesh's boundary (an edge used by one triangle): the rims
// of mouth and eye openings, the neck.
std::vector<std::uint8_t> BoundaryVertices(std::size_t vertex_count, std::span<const Triangle> triangles) {
  std::vector<std::uint8_t> on_boundary(vertex_count, 0);
  for (const BoundarySide& side : BoundarySides(triangles)) on_boundary[side.a] = on_boundary[side.b] = 1;
  return on_boundary;
}

// Per boundary vertex: the unit direction away from the rim into its own
// lip or lid (towards its neighbours' centroid, in the tangent plane); zero
// elsewhere.
std::vector<glm::vec3> InwardFromRim(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                                     std::span<const glm::vec3> normals, std::span<const std::uint8_t> on_boundary) {
  std::vector<glm::vec3> inward(positions.size(), glm::vec3(0.0f));
  std::vector<float> neighbour_count(positions.size(), 0.0f);
  for (const Triangle& t : triangles) {
    for (std::size_t k = 0; k < 3; ++k) {
      if (!on_boundary[t[k]]) continue;
      inward[t[k]] += positions[t[(k + 1) % 3]] + positions[t[(k + 2) % 3]];
      neighbour_count[t[k]] += 2.0f;
    }
  }
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (!on_boundary[v] || neighbour_count[v] == 0.0f) continue;
    glm::vec3 direction = inward[v] / neighbour_count[v] - positions[v];
    direction -= glm::dot(direction, normals[v]) * normals[v];
    const float length = glm::length(direction);
    inward[v] = length > 0.0f ? direction / length : glm::vec3(0.0f);
  }
  return inward;
}

// Where each target vertex looks for its template point: the vertex itself,
// or, on a boundary (the rim of a mouth or eye opening), a point `inset`
// (target units) into its own lip or lid. The rims are where a fitted
// template is least exact: the seam of closed lips sits a millimetre off, so
// the rim vertex itself is as near to the other lip as to its own, and would
// take the wrong lip's motion.
std::vector<glm::vec3> QueryPoints(std::span<const glm::vec3> positions, std::span<const glm::vec3> inward,
                                   float inset) {
  std::vector<glm::vec3> queries(positions.begin(), positions.end());
  for (std::size_t v = 0; v < positions.size(); ++v) queries[v] += inset * inward[v];
  return queries;
}

// An edge of the template between two rim vertices, as a side of one of its
// triangles (slots first and second of triangle `triangle`), and the
// direction from it into the opening.
struct TemplateRimEdge {
  std::uint32_t triangle;
  std::uint8_t first;
  std::uint8_t second;
  glm::vec3 into_opening;
};

std::vector<TemplateRimEdge> TemplateRimEdges(std::span<const Triangle> triangles,
                                              std::span<const TemplateRim> rims) {
  std::vector<TemplateRimEdge> edges;
  if (rims.empty()) return edges;
  const auto rim_of = [&](std::uint32_t v) -> const TemplateRim* {
    const auto it = std::lower_bound(rims.begin(), rims.end(), v,
                                     [](const TemplateRim& r, std::uint32_t x) { return r.vertex < x; });
    return it != rims.end() && it->vertex == v ? &*it : nullptr;
  };
  std::vector<std::uint64_t> seen;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (std::uint8_t e = 0; e < 3; ++e) {
      const auto next = static_cast<std::uint8_t>((e + 1) % 3);
      const std::uint32_t a = triangles[t][e], b = triangles[t][next];
      const TemplateRim* rim_a = rim_of(a);
      const TemplateRim* rim_b = rim_of(b);
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

// The nearest point to p on the template's rim edges that open the way
// `into_opening` does (cos >= min_facing), as a hit on the edge's triangle;
// triangle -1 when none lies within max_distance.
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

// Distance from rim vertex i to the nearest point of the rim's opposite side
// (its edges between consecutive loop vertices that both face against i), at
// positions + deltas (deltas may be null: at rest); 0 when the rim has none.
// *to_opposite: from vertex i to that point.
float NearestOppositeSide(const TopologyMapping::Rim& rim, std::size_t i, std::span<const glm::vec3> positions,
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
void RimBandOf(TopologyMapping::Rim& rim, float reach, std::span<const glm::vec3> positions,
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

// rim.passes passes of (previous + 2 self + next) / 4 along the rim; values
// by index into rim.vertices.
void SmoothAlongRim(const TopologyMapping::Rim& rim, std::vector<glm::vec3>& values, std::vector<glm::vec3>& scratch) {
  scratch.resize(values.size());
  for (int pass = 0; pass < rim.passes; ++pass) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      const TopologyMapping::RimNeighbours& at = rim.vertices[i];
      scratch[i] = 0.25f * (values[at.previous] + 2.0f * values[i] + values[at.next]);
    }
    values.swap(scratch);
  }
}

void CheckParams(const TopologyMappingParams& params) {
  if (!(params.full_weight_distance >= 0.0f) || !(params.zero_weight_distance > params.full_weight_distance)) {
    throw InvalidInputError("topology mapping: zero_weight_distance must exceed full_weight_distance >= 0");
  }
  if (!(params.rim_smoothing_radius >= 0.0f) || !std::isfinite(params.rim_smoothing_radius)) {
    throw InvalidInputError("topology mapping: rim_smoothing_radius must be finite and >= 0, not " +
                            std::to_string(params.rim_smoothing_radius));
  }
  if (!(params.rim_closing_ratio >= 0.0f && params.rim_closing_ratio < 1.0f) ||
      !(params.rim_closing_reach > 0.0f) || !std::isfinite(params.rim_closing_reach)) {
    throw InvalidInputError("topology mapping: rim_closing_ratio must be in [0, 1) and rim_closing_reach finite "
                            "and > 0, not " + std::to_string(params.rim_closing_ratio) + " and " +
                            std::to_string(params.rim_closing_reach));
  }
}

void CheckTemplateRims(std::span<const TemplateRim> template_rims, std::size_t template_vertices) {
  for (std::size_t i = 0; i < template_rims.size(); ++i) {
    if (template_rims[i].vertex >= template_vertices ||
        (i > 0 && !(template_rims[i - 1].vertex < template_rims[i].vertex))) {
      throw InvalidInputError("topology mapping: template rim vertex " + std::to_string(template_rims[i].vertex) +
                              " out of range or out of order (" + std::to_string(template_vertices) +
                              " vertices)");
    }
  }
}

// Per target vertex, its nearest point on the whole fitted template; per
// target part, which template parts its vertices are nearest to (within `zero`).
struct PartVotes {
  std::vector<ClosestPointHit> nearest;
  std::vector<std::map<std::uint32_t, std::size_t>> votes;
  std::vector<std::size_t> part_size;
};

PartVotes CountPartVotes(const ClosestPointQuery& whole, std::span<const Triangle> template_triangles,
                         std::span<const std::uint32_t> template_part_of_vertex,
                         std::span<const glm::vec3> target_positions,
                         std::span<const std::uint32_t> target_part_of_vertex, std::size_t target_parts, float zero) {
  const std::size_t n = target_positions.size();
  PartVotes result;
  result.votes.resize(target_parts);
  result.part_size.assign(target_parts, 0);
  result.nearest.resize(n);
  for (std::size_t v = 0; v < n; ++v) {
    result.nearest[v] = whole.Find(target_positions[v]);
    const std::uint32_t part = target_part_of_vertex[v];
    ++result.part_size[part];
    if (result.nearest[v].distance <= zero) {
      const Triangle& t = template_triangles[static_cast<std::size_t>(result.nearest[v].triangle)];
      ++result.votes[part][template_part_of_vertex[t[0]]];
    }
  }
  return result;
}

// One search structure per distinct set of chosen template parts; per target
// part the one it searches (null: nothing of the template near it).
struct PartSurfaces {
  std::map<std::vector<std::uint32_t>, PartSurface> surfaces;
  std::vector<const PartSurface*> surface_of_part;
};

PartSurfaces BuildPartSurfaces(std::span<const glm::vec3> fitted_template, std::span<const Triangle> template_triangles,
                               std::span<const std::uint32_t> template_part_of_vertex, const PartVotes& votes,
                               float min_part_vote) {
  const std::size_t target_parts = votes.votes.size();
  PartSurfaces result;
  result.surface_of_part.assign(target_parts, nullptr);
  for (std::size_t part = 0; part < target_parts; ++part) {
    std::vector<std::uint32_t> chosen;
    for (const auto& [template_part, count] : votes.votes[part]) {
      if (static_cast<float>(count) >= min_part_vote * static_cast<float>(votes.part_size[part])) {
        chosen.push_back(template_part);
      }
    }
    if (chosen.empty()) continue;  // nothing of the template near this part: plain nearest, faded out
    auto [it, inserted] = result.surfaces.try_emplace(chosen);
    if (inserted) {
      std::vector<Triangle> subset;
      for (std::size_t t = 0; t < template_triangles.size(); ++t) {
        if (std::binary_search(chosen.begin(), chosen.end(), template_part_of_vertex[template_triangles[t][0]])) {
          subset.push_back(template_triangles[t]);
          it->second.template_triangle.push_back(static_cast<std::uint32_t>(t));
        }
      }
      it->second.query = std::make_unique<ClosestPointQuery>(fitted_template, subset);
    }
    result.surface_of_part[part] = &it->second;
  }
  return result;
}

// The target as the per-vertex search sees it: normals, boundary flags, the
// direction into its own lip or lid, and the (inset) query points.
struct TargetSearchView {
  std::span<const glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<std::uint8_t> on_boundary;
  std::vector<glm::vec3> inward;
  std::vector<glm::vec3> queries;
};

TargetSearchView MakeTargetSearchView(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                                      float inset) {
  const std::size_t n = positions.size();
  TargetSearchView view;
  view.positions = positions;
  view.normals.resize(n);
  ComputeVertexNormals(positions, triangles, view.normals);
  view.on_boundary = BoundaryVertices(n, triangles);
  view.inward = InwardFromRim(positions, triangles, view.normals, view.on_boundary);
  view.queries = QueryPoints(positions, view.inward, inset);
  return view;
}

// Everything the per-vertex mapping reads, in absolute distances.
struct VertexMapper {
  std::span<const glm::vec3> fitted_template;
  std::span<const Triangle> template_triangles;
  const std::vector<TemplateRimEdge>& rim_edges;
  const TargetSearchView& target;
  const TopologyMappingParams& params;
  float rim_snap_distance;
  float zero;

  // The template point of target vertex v: on a template rim edge when it
  // snaps to one, else the nearest facing point of its part's surface, else
  // `nearest`. Counts snaps and facing fallbacks in `mapping`.
  ClosestPointHit Map(std::size_t v, ClosestPointHit nearest, const PartSurface* surface, bool& snapped,
                      TopologyMapping& mapping) const {
    const ClosestPointHit on_rim =
        target.on_boundary[v] && !rim_edges.empty()
            ? NearestOnRim(target.positions[v], -target.inward[v], fitted_template, template_triangles, rim_edges,
                           params.rim_min_facing, rim_snap_distance)
            : ClosestPointHit{};
    snapped = false;
    if (on_rim.triangle >= 0) {
      ++mapping.rim_vertices;
      snapped = true;
      return on_rim;
    }
    if (!surface) return nearest;
    ClosestPointHit facing =
        surface->query->FindFacing(target.queries[v], target.normals[v], params.min_normal_dot, zero);
    if (facing.triangle < 0) {
      facing = surface->query->Find(target.queries[v]);
      ++mapping.facing_fallbacks;
    }
    facing.triangle = static_cast<std::int32_t>(surface->template_triangle[static_cast<std::size_t>(facing.triangle)]);
    return facing;
  }
};

// Records one vertex's hit and falloff weight and counts it as full, partial or unmapped.
void RecordHit(TopologyMapping& mapping, std::size_t v, const ClosestPointHit& hit, float full, float zero,
               double& distance_sum) {
  mapping.triangle[v] = static_cast<std::uint32_t>(hit.triangle);
  mapping.barycentrics[v] = hit.barycentrics;
  mapping.weight[v] = Falloff(hit.distance, full, zero);
  if (mapping.weight[v] >= 1.0f) {
    ++mapping.full_vertices;
    distance_sum += hit.distance;
  } else if (mapping.weight[v] > 0.0f) {
    ++mapping.partial_vertices;
  } else {
    ++mapping.unmapped_vertices;
  }
}

// A target boundary loop with snapped vertices as a rim: smoothing passes for
// `radius`, same-side neighbours, the opening's direction, rest gaps and,
// when closing is on, the band of vertices that follow it.
TopologyMapping::Rim RimOfLoop(const std::vector<std::uint32_t>& loop, const TargetSearchView& target,
                               const TopologyMappingParams& params, float radius,
                               const std::vector<std::uint32_t>& neighbour_begin,
                               const std::vector<std::uint32_t>& neighbours) {
  const std::span<const glm::vec3> target_positions = target.positions;
  const std::vector<glm::vec3>& inward = target.inward;
  const std::size_t size = loop.size();
  float length = 0.0f;
  for (std::size_t i = 0; i < size; ++i) {
    length += glm::length(target_positions[loop[(i + 1) % size]] - target_positions[loop[i]]);
  }
  // k passes of the (1, 2, 1) / 4 filter: a Gaussian of variance k / 2 vertex spacings squared.
  const float spacing = length / static_cast<float>(size);
  TopologyMapping::Rim rim;
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

// The rims of the target's boundary loops that have snapped vertices.
void AddSnappedRims(TopologyMapping& mapping, const TargetSearchView& target,
                    std::span<const Triangle> target_triangles, std::span<const std::uint8_t> rim_snapped,
                    const TopologyMappingParams& params, float diagonal) {
  const std::size_t n = target.positions.size();
  mapping.rim_closing_ratio = params.rim_closing_ratio;
  std::vector<std::uint32_t> neighbour_begin, neighbours;
  if (params.rim_closing_ratio > 0.0f) VertexNeighbours(n, target_triangles, neighbour_begin, neighbours);
  const float radius = params.rim_smoothing_radius * diagonal;
  for (const std::vector<std::uint32_t>& loop : BoundaryLoops(target.positions, target_triangles)) {
    if (std::none_of(loop.begin(), loop.end(), [&](std::uint32_t v) { return rim_snapped[v] != 0; })) continue;
    mapping.rims.push_back(RimOfLoop(loop, target, params, radius, neighbour_begin, neighbours));
  }
}

}  // namespace

TopologyMapping ComputeTopologyMapping(std::span<const glm::vec3> fitted_template,
                                       std::span<const Triangle> template_triangles,
                                       std::span<const glm::vec3> target_positions,
                                       std::span<const Triangle> target_triangles,
                                       const TopologyMappingParams& params,
                                       std::span<const TemplateRim> template_rims) {
  CheckTarget(target_positions, target_triangles);
  CheckParams(params);
  const ClosestPointQuery whole(fitted_template, template_triangles);  // validates the template
  const float diagonal = BoundingDiagonalOf(fitted_template);
  const float full = params.full_weight_distance * diagonal;
  const float zero = params.zero_weight_distance * diagonal;

  std::vector<std::uint32_t> template_part_of_vertex, target_part_of_vertex;
  ConnectedComponents(fitted_template.size(), template_triangles, template_part_of_vertex);
  const std::size_t target_parts =
      ConnectedComponents(target_positions.size(), target_triangles, target_part_of_vertex);
  const PartVotes votes = CountPartVotes(whole, template_triangles, template_part_of_vertex, target_positions,
                                         target_part_of_vertex, target_parts, zero);
  const PartSurfaces surfaces =
      BuildPartSurfaces(fitted_template, template_triangles, template_part_of_vertex, votes, params.min_part_vote);

  const TargetSearchView target =
      MakeTargetSearchView(target_positions, target_triangles, params.boundary_inset * diagonal);
  CheckTemplateRims(template_rims, fitted_template.size());
  const std::vector<TemplateRimEdge> rim_edges = TemplateRimEdges(template_triangles, template_rims);
  const VertexMapper mapper{fitted_template, template_triangles, rim_edges, target, params,
                            params.rim_snap_distance * diagonal, zero};

  const std::size_t n = target_positions.size();
  TopologyMapping mapping;
  std::vector<std::uint8_t> rim_snapped(n, 0);
  mapping.triangle.resize(n);
  mapping.barycentrics.resize(n);
  mapping.weight.resize(n);
  double distance_sum = 0.0;
  for (std::size_t v = 0; v < n; ++v) {
    bool snapped = false;
    const ClosestPointHit hit =
        mapper.Map(v, votes.nearest[v], surfaces.surface_of_part[target_part_of_vertex[v]], snapped, mapping);
    rim_snapped[v] = snapped ? 1 : 0;
    RecordHit(mapping, v, hit, full, zero, distance_sum);
  }
  mapping.mean_distance = mapping.full_vertices ? distance_sum / static_cast<double>(mapping.full_vertices) : 0.0;
  if (mapping.rim_vertices > 0) AddSnappedRims(mapping, target, target_triangles, rim_snapped, params, diagonal);
  return mapping;
}

void MapVertexValues(const TopologyMapping& mapping, std::span<const Triangle> template_triangles,
                     std::span<const glm::vec3> template_values, std::vector<glm::vec3>& target_values) {
  target_values.assign(mapping.weight.size(), glm::vec3(0.0f));
  for (std::size_t v = 0; v < mapping.weight.size(); ++v) {
    if (mapping.weight[v] <= 0.0f) continue;
    const Triangle& t = template_triangles[mapping.triangle[v]];
    const glm::vec3 b = mapping.barycentrics[v];
    target_values[v] =
        mapping.weight[v] * (b.x * template_values[t[0]] + b.y * template_values[t[1]] + b.z * template_values[t[2]]);
  }
  std::vector<glm::vec3> along_rim, scratch;
  for (const TopologyMapping::Rim& rim : mapping.rims) {
    if (rim.passes == 0) continue;
    along_rim.clear();
    for (const TopologyMapping::RimNeighbours& at : rim.vertices) along_rim.push_back(target_values[at.vertex]);
    SmoothAlongRim(rim, along_rim, scratch);
    for (std::size_t i = 0; i < along_rim.size(); ++i) target_values[rim.vertices[i].vertex] = along_rim[i];
  }
}

void CloseRims(const TopologyMapping& mapping, std::span<const glm::vec3> target_positions,
               std::vector<glm::vec3>& deltas) {
  const float ratio_limit = mapping.rim_closing_ratio;
  if (!(ratio_limit > 0.0f)) return;
  std::vector<glm::vec3> correction, scratch;
  for (const TopologyMapping::Rim& rim : mapping.rims) {
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
    for (const TopologyMapping::RimBand& follower : rim.band) {
      deltas[follower.vertex] += follower.weight * correction[follower.rim_index];
    }
  }
}

RawRig MapRigToTarget(const Rig& fitted_rig, const TopologyMapping& mapping, RawRig target,
                      float relative_drop_threshold) {
  if (mapping.weight.size() != target.positions.size()) {
    throw InvalidInputError("topology mapping: the mapping has " + std::to_string(mapping.weight.size()) +
                            " vertices, the target " + std::to_string(target.positions.size()));
  }
  const std::size_t n = target.positions.size();
  const float threshold = relative_drop_threshold * BoundingDiagonalOf(target.positions);
  const bool with_normals = fitted_rig.has_normal_deltas();
  std::vector<glm::vec3> neutral_normals, normals, expression;
  if (with_normals) {
    neutral_normals.resize(n);
    normals.resize(n);
    ComputeVertexNormals(target.positions, target.triangles, neutral_normals);
  }
  std::vector<glm::vec3> template_deltas(fitted_rig.vertex_count()), target_deltas;
  std::vector<RawBlendShape> shapes;
  for (std::size_t s = 0; s < fitted_rig.shape_count(); ++s) {
    const BlendShapeView shape = fitted_rig.shape(s);
    std::fill(template_deltas.begin(), template_deltas.end(), glm::vec3(0.0f));
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      template_deltas[shape.vertex_indices[i]] = shape.position_deltas[i];
    }
    MapVertexValues(mapping, fitted_rig.triangles(), template_deltas, target_deltas);
    CloseRims(mapping, target.positions, target_deltas);
    if (with_normals) {
      expression.resize(n);
      for (std::size_t v = 0; v < n; ++v) expression[v] = target.positions[v] + target_deltas[v];
      ComputeVertexNormals(expression, target.triangles, normals);
      for (std::size_t v = 0; v < n; ++v) normals[v] -= neutral_normals[v];
    }
    shapes.push_back(MakeSparseShape(std::string(shape.name), target_deltas, normals, threshold));
  }
  // The target's own shapes stay unless a template shape has the same name.
  for (RawBlendShape& own : target.shapes) {
    const bool replaced =
        std::any_of(shapes.begin(), shapes.end(), [&](const RawBlendShape& s) { return s.name == own.name; });
    if (!replaced) shapes.push_back(std::move(own));
  }
  target.shapes = std::move(shapes);
  if (!with_normals) {
    for (RawBlendShape& shape : target.shapes) shape.normal_deltas.clear();
  }
  return target;  // the target's own normals (if any) stay
}

}  // namespace facerig
