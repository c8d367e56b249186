// The fitted template's lid margins onto the target's eye openings.
//
// Registration fits surfaces, not rims: the fitted template's lid margin can
// sit off the target's rim, which then takes the motion of a point up on the
// template's lid, which moves less, and a transferred blink leaves the eye
// partly open (README, "Measurements behind the defaults"). Where the target's opening is a hole
// in its mesh, its rim is exact: each template margin vertex (a vertex that
// meets the vertex across the opening in one of the template's expressions,
// expression_contacts.h) goes onto the nearest rim edge that faces the same
// way, and the vertices around follow smoothly (a harmonic field over the
// template's edges that fades to nothing one opening away). Deformation
// transfer then closes the fitted template's corrected opening, and the
// target's rim vertices map onto its margins.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/runtime/rig.h"

namespace facerig {

// A template vertex on the margin of an opening, and the vertex across the
// opening that it meets in one of the template's expressions.
struct OpeningMargin {
  std::uint32_t vertex;
  std::uint32_t partner;
};

// Both ends of every contact of every expression (ExpressionContactFinder),
// each vertex once (with its first partner), by increasing vertex.
// ICT-FaceKit: its eyelids (the blinks), and a few lip vertices of
// mouthRoll and jaw shapes that the alignment leaves (their partners meet no
// rim across a like opening). Its lips touch at rest: not an opening here.
std::vector<OpeningMargin> FindOpeningMargins(const Rig& template_rig);

struct MarginAlignmentParams {
  // A margin vertex takes the nearest rim point within this fraction of its
  // opening (its distance to its partner in the fit) ...
  float max_distance = 0.5f;
  // ... on a rim edge whose opening lies the same way: cos of the angle
  // between the margin's direction to its partner and the rim edge's
  // direction away from its triangle, at least this.
  float min_facing = 0.5f;
  // Only where the partner finds a rim point too, and the two rim points lie
  // across an opening 0.5 to 2 times the fit's, in the same direction
  // (cos >= min_facing).
  float min_opening_ratio = 0.5f;
  // Matches whose correction exceeds this many times the median correction
  // are dropped (a corner taking a rim point of the other lid).
  float max_correction_over_median = 3.0f;
  // The correction fades to zero at this many median openings, measured
  // along the template's edges.
  float reach = 1.0f;
};

struct MarginAlignmentResult {
  std::vector<std::uint32_t> aligned;  // margin vertices moved onto a rim (sorted)
  std::size_t aligned_vertices = 0;  // their count
  std::size_t moved_vertices = 0;    // all vertices the correction moved
  double mean_correction = 0.0;      // over the aligned margin vertices, target units
  double max_correction = 0.0;
};

// fitted: the template registered onto the target (template topology, target
// frame), corrected in place; template_triangles: the template's. Targets
// without holes near the margins are left as they are.
MarginAlignmentResult AlignMarginsToOpenings(std::span<glm::vec3> fitted, std::span<const Triangle> template_triangles,
                                             std::span<const OpeningMargin> margins,
                                             std::span<const glm::vec3> target_positions,
                                             std::span<const Triangle> target_triangles,
                                             const MarginAlignmentParams& params = {});

}  // namespace facerig
