#include "facerig/offline/mapping/topology_mapping.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <limits>
#include <memory>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/geometry/closest_point.h"
#include "facerig/offline/mapping/rigid_pieces.h"
#include "facerig/runtime/shape_names.h"
#include "facerig/offline/error.h"
#include "facerig/offline/geometry/mesh_components.h"
#include "facerig/offline/error.h"
#include "geometry/mesh_edges.h"
#include "openings/rims.h"
#include "geometry/bounding_box.h"

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

float BoundingDiagonalOf(std::span<const glm::vec3> positions) { return BoxAround(positions).diagonal(); }

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

void CheckParams(const TopologyMappingParams& params) {
  if (!(params.full_weight_distance >= 0.0f) || !(params.zero_weight_distance > params.full_weight_distance)) {
    throw InvalidInputError("topology mapping: zero_weight_distance must exceed full_weight_distance >= 0");
  }
  if (!(params.facing_reach >= 0.0f) || !std::isfinite(params.facing_reach)) {
    throw InvalidInputError("topology mapping: facing_reach must be finite and >= 0, not " +
                            std::to_string(params.facing_reach));
  }
  const OpeningParams& openings = params.openings;
  if (!(openings.rim_smoothing_radius >= 0.0f) || !std::isfinite(openings.rim_smoothing_radius)) {
    throw InvalidInputError("topology mapping: rim_smoothing_radius must be finite and >= 0, not " +
                            std::to_string(openings.rim_smoothing_radius));
  }
  if (!(openings.rim_closing_ratio >= 0.0f && openings.rim_closing_ratio < 1.0f) ||
      !(openings.rim_closing_reach > 0.0f) || !std::isfinite(openings.rim_closing_reach)) {
    throw InvalidInputError("topology mapping: rim_closing_ratio must be in [0, 1) and rim_closing_reach finite "
                            "and > 0, not " + std::to_string(openings.rim_closing_ratio) + " and " +
                            std::to_string(openings.rim_closing_reach));
  }
}

void CheckTemplateMargins(std::span<const MarginDirection> margins, std::size_t template_vertices) {
  for (std::size_t i = 0; i < margins.size(); ++i) {
    if (margins[i].vertex >= template_vertices || (i > 0 && !(margins[i - 1].vertex < margins[i].vertex))) {
      throw InvalidInputError("topology mapping: template rim vertex " + std::to_string(margins[i].vertex) +
                              " out of range or out of order (" + std::to_string(template_vertices) +
                              " vertices)");
    }
  }
}

double TriangleArea(std::span<const glm::vec3> positions, const Triangle& t) {
  return 0.5 * static_cast<double>(
                   glm::length(glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]])));
}

glm::vec3 Centroid(std::span<const glm::vec3> positions, const Triangle& t) {
  return (positions[t[0]] + positions[t[1]] + positions[t[2]]) / 3.0f;
}

// For each connected part of a mesh (`from`), the fraction of its area
// nearest to each part of another (`onto`, within `reach`), sampled at
// triangle centroids: a decimated thin part (the tear film between lid and
// eyeball) keeps mostly its border vertices, which lie where it meets its
// neighbours and are as near to them as to itself; its centroids lie inside it.
std::vector<std::map<std::uint32_t, double>> NearestPartAreas(std::span<const glm::vec3> from_positions,
                                                              std::span<const Triangle> from_triangles,
                                                              std::span<const std::uint32_t> from_part_of_vertex,
                                                              std::size_t from_parts, const ClosestPointQuery& onto,
                                                              std::span<const std::uint32_t> onto_part_of_vertex,
                                                              float reach) {
  std::vector<std::map<std::uint32_t, double>> fractions(from_parts);
  std::vector<double> part_area(from_parts, 0.0);
  for (const Triangle& t : from_triangles) {
    const double area = TriangleArea(from_positions, t);
    const std::uint32_t part = from_part_of_vertex[t[0]];
    part_area[part] += area;
    const ClosestPointHit hit = onto.Find(Centroid(from_positions, t), reach);
    if (hit.triangle >= 0) {
      fractions[part][onto_part_of_vertex[onto.triangles()[static_cast<std::size_t>(hit.triangle)][0]]] += area;
    }
  }
  for (std::size_t part = 0; part < from_parts; ++part) {
    for (auto& [onto_part, area] : fractions[part]) area = part_area[part] > 0.0 ? area / part_area[part] : 0.0;
  }
  return fractions;
}

// Which template parts each target part matches, in both directions: the
// fraction of the target part's area nearest to each template part, and of
// each template part's area nearest to each target part. One-way votes are
// not enough for thin parts that lie on others (the tear film on the eyeball,
// under the lid): a fitted template a millimetre off gives their area to the
// eyeball and the skin as much as to their own counterpart, but of the
// eyeball's or the skin's area almost none lies nearest to them.
struct PartVotes {
  std::vector<std::map<std::uint32_t, double>> target_to_template;  // [target part][template part]
  std::vector<std::map<std::uint32_t, double>> template_to_target;  // [template part][target part]
};

// One search structure per distinct set of chosen template parts and mouth
// side; per target part and side the one it searches (null: nothing of the
// template near it; for a side: no such side).
struct PartSurfaces {
  std::map<std::pair<std::vector<std::uint32_t>, MouthSide>, PartSurface> surfaces;
  std::vector<std::array<const PartSurface*, 3>> surface_of_part;

  const PartSurface* Of(std::uint32_t part, MouthSide side) const {
    const PartSurface* on_side = surface_of_part[part][static_cast<std::size_t>(side)];
    return on_side ? on_side : surface_of_part[part][0];
  }
};

// The template parts target part `part` searches: those whose mutual score
// (the product of the two fractions) reaches `min_part_vote` of the best
// one's; where no template part has any of its area nearest to this one (a
// speck), those with `min_part_vote` of its own area.
std::vector<std::uint32_t> ChooseTemplateParts(const PartVotes& votes, std::size_t part, float min_part_vote) {
  std::map<std::uint32_t, double> score;
  double best = 0.0;
  for (const auto& [template_part, forward] : votes.target_to_template[part]) {
    const auto& back = votes.template_to_target[template_part];
    const auto found = back.find(static_cast<std::uint32_t>(part));
    score[template_part] = forward * (found == back.end() ? 0.0 : found->second);
    best = std::max(best, score[template_part]);
  }
  std::vector<std::uint32_t> chosen;
  for (const auto& [template_part, forward] : votes.target_to_template[part]) {
    const bool mutual = best > 0.0 && score[template_part] >= static_cast<double>(min_part_vote) * best;
    const bool one_way = best == 0.0 && forward >= static_cast<double>(min_part_vote);
    if (mutual || one_way) chosen.push_back(template_part);
  }
  return chosen;
}

// The chosen template parts' triangles on one side of the mouth (all of
// them for kEither), with their indices in the template.
PartSurface MakePartSurface(std::span<const glm::vec3> fitted_template, std::span<const Triangle> template_triangles,
                            std::span<const std::uint32_t> template_part_of_vertex,
                            const std::vector<std::uint32_t>& chosen, MouthSide side,
                            std::span<const MouthSide> triangle_sides) {
  PartSurface surface;
  std::vector<Triangle> subset;
  for (std::size_t t = 0; t < template_triangles.size(); ++t) {
    const bool on_side = side == MouthSide::kEither || triangle_sides[t] == side;
    if (on_side && std::binary_search(chosen.begin(), chosen.end(), template_part_of_vertex[template_triangles[t][0]])) {
      subset.push_back(template_triangles[t]);
      surface.template_triangle.push_back(static_cast<std::uint32_t>(t));
    }
  }
  if (subset.empty()) return surface;
  surface.query = std::make_unique<ClosestPointQuery>(
      Mesh{.positions = {fitted_template.begin(), fitted_template.end()}, .triangles = std::move(subset)});
  return surface;
}

// sides_of_part: per target part, bit s set when some of its vertices lie on mouth side s.
PartSurfaces BuildPartSurfaces(std::span<const glm::vec3> fitted_template, std::span<const Triangle> template_triangles,
                               std::span<const std::uint32_t> template_part_of_vertex, const PartVotes& votes,
                               float min_part_vote, std::span<const std::uint8_t> sides_of_part,
                               std::span<const MouthSide> triangle_sides) {
  const std::size_t target_parts = votes.target_to_template.size();
  PartSurfaces result;
  result.surface_of_part.assign(target_parts, {nullptr, nullptr, nullptr});
  for (std::size_t part = 0; part < target_parts; ++part) {
    const std::vector<std::uint32_t> chosen = ChooseTemplateParts(votes, part, min_part_vote);
    if (chosen.empty()) continue;  // nothing of the template near this part: plain nearest, faded out
    for (MouthSide side : {MouthSide::kEither, MouthSide::kUpper, MouthSide::kLower}) {
      const auto s = static_cast<std::size_t>(side);
      if (side != MouthSide::kEither && !(sides_of_part[part] & (1u << s))) continue;
      auto [it, inserted] = result.surfaces.try_emplace({chosen, side});
      if (inserted) {
        it->second = MakePartSurface(fitted_template, template_triangles, template_part_of_vertex, chosen, side,
                                     triangle_sides);
      }
      // A side with none of the chosen parts' triangles searches them all.
      if (it->second.query) result.surface_of_part[part][s] = &it->second;
    }
  }
  return result;
}

// Per target part: bit s set when some of its vertices lie on mouth side s.
std::vector<std::uint8_t> SidesOfParts(std::span<const std::uint32_t> part_of_vertex, std::size_t parts,
                                       std::span<const MouthSide> vertex_sides) {
  std::vector<std::uint8_t> sides(parts, 0);
  for (std::size_t v = 0; v < vertex_sides.size(); ++v) {
    sides[part_of_vertex[v]] |= static_cast<std::uint8_t>(1u << static_cast<unsigned>(vertex_sides[v]));
  }
  return sides;
}

void CheckMouthSides(const MouthSides& sides, std::size_t template_triangles, std::size_t target_vertices) {
  if (sides.template_triangle.empty() && sides.target_vertex.empty()) return;
  if (sides.template_triangle.size() != template_triangles || sides.target_vertex.size() != target_vertices) {
    throw InvalidInputError("topology mapping: mouth sides for " + std::to_string(sides.template_triangle.size()) +
                            " template triangles and " + std::to_string(sides.target_vertex.size()) +
                            " target vertices, not " + std::to_string(template_triangles) + " and " +
                            std::to_string(target_vertices));
  }
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
  const ClosestPointQuery& whole;  // the whole fitted template
  std::span<const glm::vec3> fitted_template;
  std::span<const Triangle> template_triangles;
  const std::vector<TemplateRimEdge>& rim_edges;
  const TargetSearchView& target;
  const TopologyMappingParams& params;
  float rim_snap_distance;
  float facing_reach;
  float zero;

  // The template point of target vertex v: on a template rim edge when it
  // snaps to one, else the nearest facing point of its part's surface, else
  // the nearest point of the whole template. Counts snaps and facing
  // fallbacks in `mapping`.
  ClosestPointHit Map(std::size_t v, const PartSurface* surface, bool& snapped, TopologyMapping& mapping) const {
    const ClosestPointHit on_rim =
        target.on_boundary[v] && !rim_edges.empty()
            ? NearestOnRim(target.positions[v], -target.inward[v], fitted_template, template_triangles, rim_edges,
                           params.openings.rim_min_facing, rim_snap_distance)
            : ClosestPointHit{};
    snapped = false;
    if (on_rim.triangle >= 0) {
      ++mapping.rim_vertices;
      snapped = true;
      return on_rim;
    }
    if (!surface) return whole.Find(target.positions[v]);
    ClosestPointHit facing =
        surface->query->FindFacing(target.queries[v], target.normals[v], params.min_normal_dot, zero);
    // Within facing_reach of the vertex it is near enough whatever the plain nearest is.
    if (facing.triangle < 0 || facing.distance > facing_reach) {
      const ClosestPointHit plain = surface->query->Find(target.queries[v]);
      if (facing.triangle < 0 || facing.distance > plain.distance + facing_reach) {
        facing = plain;
        ++mapping.facing_fallbacks;
      }
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

}  // namespace

TopologyMapping ComputeTopologyMapping(const Mesh& fitted_template_mesh, const Mesh& target_mesh,
                                       const TopologyMappingParams& params,
                                       std::span<const MarginDirection> template_margins,
                                       const MouthSides& mouth_sides) {
  const std::span<const glm::vec3> fitted_template = fitted_template_mesh.positions;
  const std::span<const Triangle> template_triangles = fitted_template_mesh.triangles;
  const std::span<const glm::vec3> target_positions = target_mesh.positions;
  const std::span<const Triangle> target_triangles = target_mesh.triangles;
  CheckTarget(target_positions, target_triangles);
  CheckParams(params);
  const ClosestPointQuery whole(fitted_template_mesh);  // validates the template
  const float diagonal = BoundingDiagonalOf(fitted_template);
  const float full = params.full_weight_distance * diagonal;
  const float zero = params.zero_weight_distance * diagonal;

  std::vector<std::uint32_t> template_part_of_vertex, target_part_of_vertex;
  const std::size_t template_parts =
      ConnectedComponents(fitted_template.size(), template_triangles, template_part_of_vertex);
  const std::size_t target_parts =
      ConnectedComponents(target_positions.size(), target_triangles, target_part_of_vertex);
  const ClosestPointQuery target_surface(Mesh{.positions = {target_positions.begin(), target_positions.end()},
                                              .triangles = {target_triangles.begin(), target_triangles.end()}});
  const PartVotes votes{
      NearestPartAreas(target_positions, target_triangles, target_part_of_vertex, target_parts, whole,
                       template_part_of_vertex, zero),
      NearestPartAreas(fitted_template, template_triangles, template_part_of_vertex, template_parts, target_surface,
                       target_part_of_vertex, zero)};
  CheckMouthSides(mouth_sides, template_triangles.size(), target_positions.size());
  const std::vector<std::uint8_t> sides_of_part =
      SidesOfParts(target_part_of_vertex, target_parts, mouth_sides.target_vertex);
  const PartSurfaces surfaces = BuildPartSurfaces(fitted_template, template_triangles, template_part_of_vertex, votes,
                                                  params.min_part_vote, sides_of_part, mouth_sides.template_triangle);

  const TargetSearchView target =
      MakeTargetSearchView(target_positions, target_triangles, params.openings.boundary_inset * diagonal);
  CheckTemplateMargins(template_margins, fitted_template.size());
  const std::vector<TemplateRimEdge> rim_edges = TemplateRimEdges(template_triangles, template_margins);
  const VertexMapper mapper{whole, fitted_template, template_triangles, rim_edges, target, params,
                            params.openings.rim_snap_distance * diagonal, params.facing_reach * diagonal, zero};

  const std::size_t n = target_positions.size();
  TopologyMapping mapping;
  std::vector<std::uint8_t> rim_snapped(n, 0);
  mapping.triangle.resize(n);
  mapping.barycentrics.resize(n);
  mapping.weight.resize(n);
  double distance_sum = 0.0;
  for (std::size_t v = 0; v < n; ++v) {
    bool snapped = false;
    const MouthSide side = mouth_sides.target_vertex.empty() ? MouthSide::kEither : mouth_sides.target_vertex[v];
    const ClosestPointHit hit = mapper.Map(v, surfaces.Of(target_part_of_vertex[v], side), snapped, mapping);
    rim_snapped[v] = snapped ? 1 : 0;
    RecordHit(mapping, v, hit, full, zero, distance_sum);
  }
  mapping.mouth_upper_vertices = mouth_sides.upper_vertices;
  mapping.mouth_lower_vertices = mouth_sides.lower_vertices;
  mapping.mean_distance = mapping.full_vertices ? distance_sum / static_cast<double>(mapping.full_vertices) : 0.0;
  if (mapping.rim_vertices > 0) {
    AddSnappedRims(mapping, target_positions, target.inward, target_triangles, rim_snapped, params.openings, diagonal);
  }
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
  for (const OpeningRim& rim : mapping.rims) {
    if (rim.passes == 0) continue;
    along_rim.clear();
    for (const RimNeighbours& at : rim.vertices) along_rim.push_back(target_values[at.vertex]);
    SmoothAlongRim(rim, along_rim, scratch);
    for (std::size_t i = 0; i < along_rim.size(); ++i) target_values[rim.vertices[i].vertex] = along_rim[i];
  }
}

namespace {

// A template shape that replaces a target's own shape: the same name in any
// spelling ("eyeBlinkLeft" and "eyeBlink_L"), or one side of an unsided
// target shape ("browInnerUp_L" replaces "browInnerUp").
bool SameShapeMeaning(std::string_view target_name, std::string_view template_name) {
  const CanonicalShapeName target = CanonicalShapeNameOf(target_name);
  const CanonicalShapeName from_template = CanonicalShapeNameOf(template_name);
  return target.base == from_template.base && (target.side == from_template.side || target.side == 0);
}

}  // namespace

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
  const std::vector<std::vector<std::uint32_t>> rigid_pieces = RigidPieces(target);
  for (std::size_t s = 0; s < fitted_rig.shape_count(); ++s) {
    const BlendShapeView shape = fitted_rig.shape(s);
    std::fill(template_deltas.begin(), template_deltas.end(), glm::vec3(0.0f));
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      template_deltas[shape.vertex_indices[i]] = shape.position_deltas[i];
    }
    MapVertexValues(mapping, fitted_rig.triangles(), template_deltas, target_deltas);
    CloseRims(mapping, target.positions, target_deltas);
    MoveRigidPiecesRigidly(rigid_pieces, target.positions, target_deltas);
    if (with_normals) {
      expression.resize(n);
      for (std::size_t v = 0; v < n; ++v) expression[v] = target.positions[v] + target_deltas[v];
      ComputeVertexNormals(expression, target.triangles, normals);
      for (std::size_t v = 0; v < n; ++v) normals[v] -= neutral_normals[v];
    }
    shapes.push_back(MakeSparseShape(std::string(shape.name), target_deltas, normals, threshold));
  }
  // The target's own shapes stay unless a template shape means the same.
  for (RawBlendShape& own : target.shapes) {
    const bool replaced = std::any_of(shapes.begin(), shapes.end(),
                                      [&](const RawBlendShape& s) { return SameShapeMeaning(own.name, s.name); });
    if (!replaced) shapes.push_back(std::move(own));
  }
  target.shapes = std::move(shapes);
  if (!with_normals) {
    for (RawBlendShape& shape : target.shapes) shape.normal_deltas.clear();
  }
  return target;  // the target's own normals (if any) stay
}

}  // namespace facerig
