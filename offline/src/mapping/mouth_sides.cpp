#include "facerig/offline/mapping/mouth_sides.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include <glm/geometric.hpp>

#include "facerig/offline/openings/eyes.h"
#include "facerig/offline/openings/gaps.h"
#include "facerig/offline/error.h"
#include "facerig/offline/geometry/stats.h"
#include "facerig/runtime/shape_names.h"
#include "facerig/offline/geometry/mesh_components.h"
#include "geometry/mesh_edges.h"

namespace facerig {
namespace {

// The template's neutral plus one ARKit shape at full weight; nothing when
// the template has no such shape.
std::optional<std::vector<glm::vec3>> PoseOf(const Rig& rig, std::string_view arkit_name,
                                             std::span<const glm::vec3> base) {
  const std::vector<std::size_t> found = FindShapesByArkitName(rig, arkit_name);
  if (found.empty()) return std::nullopt;
  std::vector<glm::vec3> pose(base.begin(), base.end());
  const BlendShapeView shape = rig.shape(found.front());
  for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) pose[shape.vertex_indices[i]] += shape.position_deltas[i];
  return pose;
}

// The lip seam of the fitted template (template frame): where each upper
// margin vertex meets its lower partner, at rest.
struct Seam {
  std::vector<glm::vec3> points;
  float centre_x = 0.0f;
  float width = 0.0f;
  float front_z = -std::numeric_limits<float>::infinity();

  // The seam's height at x: that of its point nearest in x.
  float HeightAt(float x) const;
  // The seam's depth (forward coordinate) at x: that of its point nearest in x.
  float DepthAt(float x) const;
};

const glm::vec3& NearestInX(const std::vector<glm::vec3>& points, float x) {
  return *std::min_element(points.begin(), points.end(), [x](const glm::vec3& a, const glm::vec3& b) {
    return std::abs(a.x - x) < std::abs(b.x - x);
  });
}

float NearestInXHeight(const std::vector<glm::vec3>& points, float x) { return NearestInX(points, x).y; }

float Seam::HeightAt(float x) const { return NearestInXHeight(points, x); }
float Seam::DepthAt(float x) const { return NearestInX(points, x).z; }

Seam SeamOf(const OpeningMargins& lips, std::span<const glm::vec3> fitted_in_template) {
  Seam seam;
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (std::size_t i = 0; i < lips.upper.size(); ++i) {
    const glm::vec3 p = 0.5f * (fitted_in_template[lips.upper[i]] + fitted_in_template[lips.lower[i]]);
    seam.points.push_back(p);
    lo = std::min(lo, p.x);
    hi = std::max(hi, p.x);
    seam.front_z = std::max(seam.front_z, p.z);
  }
  seam.centre_x = 0.5f * (lo + hi);
  seam.width = hi - lo;
  return seam;
}

// Template triangles the jaw carries (kLower) and those it leaves (kUpper):
// the jaw's motion is about a rigid turn (fitted to the lower lip's), so a
// vertex far back (the tongue, near the hinge) moves less than the lower lip
// yet with the jaw. A vertex moving more than half what the jaw's turn would
// move it (at least a tenth of the lower lip's motion) is on the jaw. Beyond
// the face region (ICT-FaceKit: head and neck, mouth socket, gums and tongue,
// teeth) so is one moving over a third of the lower lip's motion: the turn, fitted to the lip alone,
// is poorly known that far back, and ICT-FaceKit's tongue root (moving half
// as much as its lip) passed for still, so the back of a mouth sack's palate
// took it and followed the jaw.
std::vector<MouthSide> TriangleSides(const Rig& template_rig, std::span<const glm::vec3> open,
                                     const OpeningMargins& lips, std::uint32_t region_vertex_count) {
  const std::span<const glm::vec3> neutral = template_rig.positions();
  const SimilarityTransform jaw = FitRigid(neutral, open, lips.lower);
  std::vector<float> lower_lip_motion;
  for (std::uint32_t v : lips.lower) lower_lip_motion.push_back(glm::length(open[v] - neutral[v]));
  const float lip_motion = Median(std::move(lower_lip_motion));
  const float floor = 0.1f * lip_motion;
  std::vector<std::uint8_t> on_jaw(neutral.size());
  for (std::size_t v = 0; v < neutral.size(); ++v) {
    const float turned = std::max(floor, glm::length(jaw.Apply(neutral[v]) - neutral[v]));
    const float moved = glm::length(open[v] - neutral[v]);
    const bool inside_mouth = v >= region_vertex_count;
    on_jaw[v] = moved > 0.5f * turned || (inside_mouth && moved > lip_motion / 3.0f) ? 1 : 0;
  }
  std::vector<MouthSide> sides;
  sides.reserve(template_rig.triangles().size());
  for (const Triangle& t : template_rig.triangles()) {
    sides.push_back(on_jaw[t[0]] + on_jaw[t[1]] + on_jaw[t[2]] >= 2 ? MouthSide::kLower : MouthSide::kUpper);
  }
  return sides;
}

// A target's mouth opening, where it is a hole in its mesh (template frame):
// the boundary loop about the template's seam, split at its corners (least
// and greatest x) into its upper and lower chains.
struct MouthRim {
  std::vector<glm::vec3> upper, lower;
  std::vector<std::pair<std::uint32_t, MouthSide>> chain_vertices;
};

std::optional<MouthRim> RimOf(const std::vector<std::uint32_t>& loop, std::span<const glm::vec3> in_template,
                              const Seam& seam) {
  std::size_t first = 0, last = 0;
  glm::vec3 centre(0.0f);
  for (std::size_t i = 0; i < loop.size(); ++i) {
    centre += in_template[loop[i]] / static_cast<float>(loop.size());
    if (in_template[loop[i]].x < in_template[loop[first]].x) first = i;
    if (in_template[loop[i]].x > in_template[loop[last]].x) last = i;
  }
  const float width = in_template[loop[last]].x - in_template[loop[first]].x;
  if (width < 0.5f * seam.width || width > 1.5f * seam.width) return std::nullopt;
  if (glm::length(centre - glm::vec3(seam.centre_x, seam.HeightAt(seam.centre_x), seam.front_z)) > 0.3f * seam.width) {
    return std::nullopt;
  }
  std::array<std::vector<std::uint32_t>, 2> chains;  // first -> last, last -> first (corners excluded)
  for (std::size_t i = (first + 1) % loop.size(); i != last; i = (i + 1) % loop.size()) chains[0].push_back(loop[i]);
  for (std::size_t i = (last + 1) % loop.size(); i != first; i = (i + 1) % loop.size()) chains[1].push_back(loop[i]);
  auto mean_y = [&](const std::vector<std::uint32_t>& chain) {
    float sum = 0.0f;
    for (std::uint32_t v : chain) sum += in_template[v].y;
    return chain.empty() ? 0.0f : sum / static_cast<float>(chain.size());
  };
  const std::size_t up = mean_y(chains[0]) >= mean_y(chains[1]) ? 0 : 1;
  MouthRim rim;
  for (std::uint32_t v : chains[up]) {
    rim.upper.push_back(in_template[v]);
    rim.chain_vertices.emplace_back(v, MouthSide::kUpper);
  }
  for (std::uint32_t v : chains[1 - up]) {
    rim.lower.push_back(in_template[v]);
    rim.chain_vertices.emplace_back(v, MouthSide::kLower);
  }
  if (rim.upper.empty() || rim.lower.empty()) return std::nullopt;
  return rim;
}

// Where the target's mouth is a hole, its own rim is the seam (the template's
// lips, fitted a millimetre off, would put the rim's vertices on either side),
// and its chains say each rim vertex's side.
bool UseTargetRims(std::span<const glm::vec3> in_template, std::span<const Triangle> target_triangles, Seam& seam,
                   std::vector<MouthSide>& chain_side) {
  std::optional<MouthRim> front;
  for (const std::vector<std::uint32_t>& loop : BoundaryLoops(in_template, target_triangles)) {
    std::optional<MouthRim> rim = RimOf(loop, in_template, seam);
    if (!rim) continue;
    for (const auto& [v, side] : rim->chain_vertices) chain_side[v] = side;
    if (!front || rim->upper.front().z > front->upper.front().z) front = std::move(rim);
  }
  if (!front) return false;
  std::vector<glm::vec3> points;
  for (const glm::vec3& p : front->upper) {
    points.push_back({p.x, 0.5f * (p.y + NearestInXHeight(front->lower, p.x)), p.z});
  }
  seam.points = std::move(points);
  return true;
}

// Per target vertex, how far along its own surface (mesh edges) the nearest
// vertex of each rim chain lies: [0] the upper, [1] the lower; infinity
// beyond `reach` or on parts not attached to the rim (its tongue, teeth).
std::array<std::vector<float>, 2> ChainDistances(std::span<const glm::vec3> positions,
                                                 std::span<const Triangle> triangles,
                                                 std::span<const MouthSide> chain_side, float reach) {
  std::vector<std::uint32_t> begin, neighbours;
  VertexNeighbours(positions.size(), triangles, begin, neighbours);
  std::array<std::vector<float>, 2> distances;
  for (MouthSide side : {MouthSide::kUpper, MouthSide::kLower}) {
    std::vector<std::uint32_t> chain;
    for (std::uint32_t v = 0; v < chain_side.size(); ++v) {
      if (chain_side[v] == side) chain.push_back(v);
    }
    const std::vector<float> reaches(chain.size(), reach);
    std::vector<float>& distance = distances[side == MouthSide::kUpper ? 0 : 1];
    distance.assign(positions.size(), std::numeric_limits<float>::infinity());
    for (const EdgeReach& at : VerticesWithinReach(positions, begin, neighbours, chain, reaches)) {
      distance[at.vertex] = at.distance;
    }
  }
  return distances;
}

// Per target vertex: 1 when its connected part lies mostly in the mouth zone
// (a mouth sack, a lining of the lips), 0 on the face's skin. On the skin,
// the way round a mouth corner makes the chin about as near the upper lip as
// the lower (within 20 %), so there the height decides.
std::vector<std::uint8_t> PartsInsideMouth(std::span<const Triangle> triangles, std::span<const MouthSide> by_height) {
  std::vector<std::uint32_t> part;
  const std::size_t parts = ConnectedComponents(by_height.size(), triangles, part);
  std::vector<std::size_t> in_zone(parts, 0), total(parts, 0);
  for (std::size_t v = 0; v < by_height.size(); ++v) {
    ++total[part[v]];
    in_zone[part[v]] += by_height[v] != MouthSide::kEither ? 1 : 0;
  }
  std::vector<std::uint8_t> inside(by_height.size());
  for (std::size_t v = 0; v < by_height.size(); ++v) inside[v] = 2 * in_zone[part[v]] >= total[part[v]] ? 1 : 0;
  return inside;
}

// Which side a vertex inside the mouth zone belongs to: the lip its own
// surface leads to (the inner side of a lip, the mouth sack's roof or floor
// hanging from it), else (a part of its own, as a tongue) its height. The
// seam's height alone fails deep in the mouth: a few degrees between the
// template's frame and the target's put the back of the head's mouth sack,
// where roof and floor meet at the seam's height, below it, and the
// palate's back wall followed the jaw. Where the two lips are about equally
// far (that meeting line), the vertex stays with the skull.
MouthSide SideByChains(std::size_t v, const std::array<std::vector<float>, 2>& chain_distance,
                       MouthSide by_height, const MouthSideParams& params) {
  if (!params.along_surface) return by_height;
  const float up = chain_distance[0][v], down = chain_distance[1][v];
  if (std::isinf(up) && std::isinf(down)) return by_height;
  return down < params.lower_share * up ? MouthSide::kLower : MouthSide::kUpper;
}

MouthSide SideInZone(glm::vec3 p, const Seam& seam, const MouthSideParams& params) {
  const float w = seam.width;
  if (std::abs(p.x - seam.centre_x) > 0.5f * w) return MouthSide::kEither;
  if (p.z > seam.front_z + params.zone_front * w || p.z < seam.front_z - params.zone_behind * w) {
    return MouthSide::kEither;
  }
  // In front of the rim (the outer lips) the plain search is right; a lip
  // bulging above or below the seam's height would take the other side.
  if (p.z > seam.DepthAt(p.x) + params.rim_front * w) return MouthSide::kEither;
  const float above = p.y - seam.HeightAt(p.x);
  if (above > params.zone_above * w || above < -params.zone_below * w) return MouthSide::kEither;
  return above >= 0.0f ? MouthSide::kUpper : MouthSide::kLower;
}

}  // namespace

MouthSides FindMouthSides(const Rig& template_rig, std::span<const glm::vec3> fitted,
                          const SimilarityTransform& to_template, std::span<const glm::vec3> target_positions,
                          std::span<const Triangle> target_triangles, std::uint32_t region_vertex_count,
                          const MouthSideParams& params) {
  MouthSides sides;
  const std::optional<std::vector<glm::vec3>> open = PoseOf(template_rig, "jawOpen", template_rig.positions());
  if (!open) return sides;
  const std::optional<std::vector<glm::vec3>> closed = PoseOf(template_rig, "mouthClose", *open);
  if (!closed) return sides;
  OpeningMargins lips;
  try {
    lips = FindLipMargins(template_rig.positions(), *open, *closed, 0, region_vertex_count);
  } catch (const MeshInputError&) {
    return sides;  // the template's lips meet nowhere: no seam to split the mouth by
  }
  std::vector<glm::vec3> fitted_in_template(fitted.size());
  for (std::size_t v = 0; v < fitted.size(); ++v) fitted_in_template[v] = to_template.Apply(fitted[v]);
  Seam seam = SeamOf(lips, fitted_in_template);
  if (!(seam.width > 0.0f)) return sides;
  std::vector<glm::vec3> target_in_template(target_positions.size());
  for (std::size_t v = 0; v < target_positions.size(); ++v) target_in_template[v] = to_template.Apply(target_positions[v]);
  std::vector<MouthSide> chain_side(target_positions.size(), MouthSide::kEither);
  // Without a mouth rim of its own the target's seam is the fitted
  // template's, a few millimetres off: its lips would search the wrong side
  // (an ICT-like face's expressions measured worse), so no sides.
  if (!UseTargetRims(target_in_template, target_triangles, seam, chain_side)) return sides;
  sides.template_triangle = TriangleSides(template_rig, *open, lips, region_vertex_count);
  sides.target_vertex.resize(target_positions.size());
  std::vector<MouthSide> by_height(target_positions.size());
  for (std::size_t v = 0; v < target_positions.size(); ++v) by_height[v] = SideInZone(target_in_template[v], seam, params);
  const std::vector<std::uint8_t> inside = PartsInsideMouth(target_triangles, by_height);
  const std::array<std::vector<float>, 2> chain_distance =
      params.along_surface
          ? ChainDistances(target_in_template, target_triangles, chain_side, params.chain_reach * seam.width)
          : std::array<std::vector<float>, 2>{};
  for (std::size_t v = 0; v < target_positions.size(); ++v) {
    if (chain_side[v] != MouthSide::kEither || by_height[v] == MouthSide::kEither || !inside[v]) {
      sides.target_vertex[v] = chain_side[v] != MouthSide::kEither ? chain_side[v] : by_height[v];
    } else {
      sides.target_vertex[v] = SideByChains(v, chain_distance, by_height[v], params);
    }
    sides.upper_vertices += sides.target_vertex[v] == MouthSide::kUpper ? 1 : 0;
    sides.lower_vertices += sides.target_vertex[v] == MouthSide::kLower ? 1 : 0;
  }
  return sides;
}

}  // namespace facerig
