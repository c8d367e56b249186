// The rims of openings in topology mapping: the fitted template's rim edges
// a target boundary vertex snaps to, the target's rims (OpeningRim: loops
// with snapped vertices) with their smoothing and closing band, and the
// closing itself (CloseRims, declared in topology_mapping.h).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/offline/geometry/closest_point.h"
#include "facerig/offline/openings/openings.h"
#include "facerig/offline/mapping/topology_mapping.h"

namespace facerig {

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
                                              std::span<const MarginDirection> margins);

// The nearest point to p on the template's rim edges that open the way
// `into_opening` does (cos >= min_facing), as a hit on the edge's triangle;
// triangle -1 when none lies within max_distance.
ClosestPointHit NearestOnRim(glm::vec3 p, glm::vec3 into_opening, std::span<const glm::vec3> fitted,
                             std::span<const Triangle> triangles, std::span<const TemplateRimEdge> edges,
                             float min_facing, float max_distance);

// rim.passes passes of (previous + 2 self + next) / 4 along the rim; values
// by index into rim.vertices.
void SmoothAlongRim(const OpeningRim& rim, std::vector<glm::vec3>& values, std::vector<glm::vec3>& scratch);

// The rims of the target's boundary loops that have snapped vertices
// (rim_snapped per target vertex); `inward`: per target vertex, the direction
// into its own lip or lid.
void AddSnappedRims(TopologyMapping& mapping, std::span<const glm::vec3> target_positions,
                    std::span<const glm::vec3> inward, std::span<const Triangle> target_triangles,
                    std::span<const std::uint8_t> rim_snapped, const OpeningParams& params, float diagonal);

}  // namespace facerig
