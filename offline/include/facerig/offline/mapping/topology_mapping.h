// Blend shapes onto the user's own mesh: a template fitted to the
// target (template topology, target frame) carries the transferred
// expressions; every target vertex takes the deltas of its closest point on
// the fitted template, interpolated with that point's barycentrics, and fades
// to zero where the target has no template counterpart (the back of a body,
// a hat), so the target's vertex order, UVs and parts stay untouched.
//
// Which template surface a target vertex may land on: each connected part of
// the target is matched to the template parts (skin, eyeballs, teeth...)
// that are nearest to it and it to them, by area both ways, and only those
// are searched, so an eyelid vertex does not take the eyeball's deltas; in the
// mouth, only the template's triangles on the vertex's side of the lip seam
// (mouth_sides.h), so the upper lip and palate do not follow the jaw. Within them the
// nearest triangle facing the same way as the target vertex's normal wins, so
// lips that touch in the neutral do not swap their motion; and a vertex on the
// rim of an opening looks from slightly inside its own lip or lid.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/offline/mapping/mouth_sides.h"
#include "facerig/offline/openings/openings.h"
#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {

struct TopologyMappingParams {
  // Distances as fractions of the fitted template's bounding-box diagonal:
  // full deltas up to full_weight_distance from the fitted template, fading
  // smoothly (smoothstep) to none at zero_weight_distance.
  float full_weight_distance = 0.02f;
  float zero_weight_distance = 0.08f;
  // A target part searches the template parts whose mutual score reaches
  // this fraction of the best one's: the fraction of the target part's area
  // nearest to the template part times the fraction of the template part's
  // area nearest to the target part. An eyeball of a face with ICT's topology
  // has a fifth of its area nearest to the lids in front of it, and the tear
  // film of a decimated face a third nearest to the skin and a fifth to the
  // eyeball (a fit a millimetre off), but of the skin's and the eyeball's
  // area almost none lies nearest to them. Where no template part has any of
  // its area nearest to the target part: those with this fraction of its area.
  float min_part_vote = 0.30f;
  // Nearest triangle with face normal . vertex normal >= this (cos 75
  // degrees); when none lies within zero_weight_distance, the plain nearest.
  float min_normal_dot = 0.26f;
  // A facing triangle is taken only this much farther than the plain nearest
  // one: a lip resting on the other lies well within it, while a vertex whose
  // normal is off (a fold of slivers on a decimated mesh) must not jump to
  // another sheet of its part centimetres away.
  float facing_reach = 0.005f;
  // The rims of the target's openings: the inset of boundary vertices, their
  // snapping onto the template's margins, smoothing along them and closing
  // (boundary_inset, rim_*; BuildRig sets these from BuildRigParams::openings).
  OpeningParams openings;
};

struct TopologyMapping {
  // Per target vertex: the fitted template triangle and barycentrics of its
  // closest point, and the falloff weight in [0, 1] (0: not mapped).
  std::vector<std::uint32_t> triangle;
  std::vector<glm::vec3> barycentrics;
  std::vector<float> weight;
  std::size_t full_vertices = 0;     // weight 1
  std::size_t partial_vertices = 0;  // 0 < weight < 1
  std::size_t unmapped_vertices = 0;  // weight 0
  std::size_t facing_fallbacks = 0;  // no facing triangle near: plain nearest used
  std::size_t rim_vertices = 0;      // target boundary vertices mapped onto a template rim edge
  std::size_t mouth_upper_vertices = 0;  // target vertices that searched the template's upper mouth side
  std::size_t mouth_lower_vertices = 0;  // ... its lower (jaw) side
  // The target's rims with snapped vertices (its eye openings, found by the
  // template's margins), smoothed by MapVertexValues and closed by CloseRims
  // (OpeningParams::rim_smoothing_radius, rim_closing_ratio).
  std::vector<OpeningRim> rims;
  float rim_closing_ratio = 0.0f;
  double mean_distance = 0.0;        // over full-weight vertices, target units
};

// fitted_template: the template registered onto the target (target frame
// and units);
// template_margins: the fitted template's margins with their directions
// across the opening (MarginDirections), by increasing vertex, or empty;
// mouth_sides: per template triangle and target vertex (FindMouthSides), or
// empty: a target vertex on one side of the mouth searches only the
// template's triangles on that side.
// \throw InvalidInputError on empty meshes, indices out of range, NaN,
// mouth sides of other sizes.
TopologyMapping ComputeTopologyMapping(const Mesh& fitted_template, const Mesh& target,
                                       const TopologyMappingParams& params = {},
                                       std::span<const MarginDirection> template_margins = {},
                                       const MouthSides& mouth_sides = {});

// Per-vertex template values (deltas: #template vertices) -> per target vertex
// (weight * barycentric interpolation, then smoothed along the rims).
// target_values gets #target vertices.
void MapVertexValues(const TopologyMapping& mapping, std::span<const Triangle> template_triangles,
                     std::span<const glm::vec3> template_values, std::vector<glm::vec3>& target_values);

// Closes the target's rims where the mapped deltas (#target vertices) bring
// their two sides together (OpeningParams::rim_closing_ratio).
// target_positions: the target's rest positions.
void CloseRims(const TopologyMapping& mapping, std::span<const glm::vec3> target_positions,
               std::vector<glm::vec3>& deltas);

// A rig on the target's topology: the target's positions, triangles, UVs,
// parts and units, with every shape of `fitted_rig` (template topology, already
// in the target's frame and units) mapped onto it. Normal deltas, when the
// fitted rig has them, are recomputed on the target from its mapped meshes.
// Deltas shorter than relative_drop_threshold x the target's diagonal are dropped.
RawRig MapRigToTarget(const Rig& fitted_rig, const TopologyMapping& mapping, RawRig target,
                      float relative_drop_threshold = 1e-6f);

}  // namespace facerig
