// Opening margins: the template vertices that meet across an eye or the mouth
// in an expression, and their alignment onto a target's rims in registration.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/offline/openings/openings.h"
#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"

namespace facerig {

// Both ends of every contact of every expression (ContactFinder), each vertex
// once (with its first partner), by increasing vertex. ICT-FaceKit: its
// eyelids (the blinks), and a few lip vertices of mouthRoll and jaw shapes
// that the alignment leaves (their partners meet no rim across a like
// opening). Its lips touch at rest: not an opening here.
std::vector<OpeningMargin> FindOpeningMargins(const Rig& template_rig, const OpeningParams& params = {});

struct MarginAlignmentResult {
  std::vector<std::uint32_t> aligned;  // margin vertices moved onto a rim (sorted)
  std::size_t aligned_vertices = 0;  // their count
  std::size_t moved_vertices = 0;    // all vertices the correction moved
  double mean_correction = 0.0;      // over the aligned margin vertices, target units
  double max_correction = 0.0;
};

// The fitted template's margins onto the target's rims where the target's
// opening is a hole in its mesh (its rim is then exact): each margin vertex
// goes onto the nearest rim edge that faces the same way, and the vertices
// around follow smoothly (a harmonic field over the template's edges that
// fades to nothing one opening away). Deformation transfer then closes the
// fitted template's corrected opening, and the target's rim vertices map onto
// its margins. fitted: the template registered onto the target (template
// topology, target frame), corrected in place; template_triangles: the
// template's. Targets without holes near the margins are left as they are.
MarginAlignmentResult AlignMarginsToOpenings(std::span<glm::vec3> fitted, std::span<const Triangle> template_triangles,
                                             std::span<const OpeningMargin> margins,
                                             std::span<const glm::vec3> target_positions,
                                             std::span<const Triangle> target_triangles,
                                             const OpeningParams& params = {});

// The margins that the mapping snaps the target's rims to: those in `aligned`
// (sorted), with the direction towards their partner in `fitted`.
std::vector<MarginDirection> MarginDirections(std::span<const OpeningMargin> margins,
                                              std::span<const std::uint32_t> aligned,
                                              std::span<const glm::vec3> fitted);

}  // namespace facerig
