// Blend shapes onto the user's own mesh: a template fitted to the
// target (template topology, target frame) carries the transferred
// expressions; every target vertex takes the deltas of its closest point on
// the fitted template, interpolated with that point's barycentrics, and fades
// to zero where the target has no template counterpart (the back of a body,
// a hat), so the target's vertex order, UVs and parts stay untouched.
//
// Which template surface a target vertex may land on: each connected part of
// the target votes (its vertices' nearest template parts) for the template
// parts it matches (skin, eyeballs, teeth...), and only those are searched,
// so an eyelid vertex does not take the eyeball's deltas. Within them the
// nearest triangle facing the same way as the target vertex's normal wins, so
// lips that touch in the neutral do not swap their motion; and a vertex on the
// rim of an opening looks from slightly inside its own lip or lid.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

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
  // A target part searches the template parts that got at least this fraction
  // of its vertices' votes.
  float min_part_vote = 0.05f;
  // Nearest triangle with face normal . vertex normal >= this (cos 75
  // degrees); when none lies within zero_weight_distance, the plain nearest.
  float min_normal_dot = 0.26f;
  // Vertices on the target's boundary (the rims of mouth and eye openings)
  // look for their template point this far (fraction of the fitted template's
  // diagonal; 0.003 is 1.4 mm on ICT-FaceKit) inside their own lip or lid.
  float boundary_inset = 0.003f;
  // Target boundary vertices within this fraction of the fitted template's
  // diagonal of a rim edge of the template (both ends in template_rims, see
  // ComputeTopologyMapping) that opens the same way (cos >= rim_min_facing)
  // take their point on that edge instead, with no inset: the upper rim of
  // an eye or a mouth moves as the template's upper margin.
  float rim_snap_distance = 0.002f;
  float rim_min_facing = 0.5f;
  // Along a target boundary loop with snapped vertices, the mapped values are
  // smoothed over about this distance (fraction of the fitted template's
  // diagonal; a Gaussian's sigma, by passes of (previous + 2 self + next) / 4,
  // neighbours facing the same way only, so an eye's corners stay apart).
  // Why: where the template's margin ends before the target's rim does, the
  // rim vertices past it take an inset point, which moves less, and a closed
  // lid's edge steps between neighbours (README, "Measurements behind the
  // defaults"). A coarse rim (vertices further apart than the radius) is left
  // as it is. 0: off.
  float rim_smoothing_radius = 0.002f;
  // Where an expression brings a rim's two sides to within this fraction of
  // their rest distance (the fitted template's lids meeting on a blink), the
  // target's rim closes: each side moves half the remaining gap towards the
  // other (or back, where they cross; fully from half this fraction down),
  // and the lid around follows, fading to nothing rim_closing_reach times the
  // rest distance away. Why: the template's lid, fitted to a surface, is
  // shaped unlike the target's, so its closed rim can leave a slit that shows
  // the eye, or cross the lower rim (README, "Measurements behind the
  // defaults"). 0: off.
  float rim_closing_ratio = 0.3f;
  float rim_closing_reach = 0.5f;
};

// A fitted template vertex on the margin of an opening (an eyelid's, a lip's)
// and the unit direction from it across the opening, in the target's frame.
struct TemplateRim {
  std::uint32_t vertex;
  glm::vec3 into_opening;
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
  // The target's rims with snapped vertices (its eye openings, found by the
  // template's margins): per rim, its vertices with their neighbours along it
  // (indices into Rim::vertices; itself where a neighbour faces another way)
  // and the number of smoothing
  // passes for its vertex spacing (TopologyMappingParams::rim_smoothing_radius,
  // applied by MapVertexValues); per vertex, the direction into the opening
  // and the rest distance to the opposite side (0: none), and the target
  // vertices that follow a closing (rim_closing_ratio, applied by CloseRims).
  struct RimNeighbours {
    std::uint32_t vertex;    // target vertex
    std::uint32_t previous;  // index into Rim::vertices
    std::uint32_t next;
  };
  struct RimBand {
    std::uint32_t vertex;
    std::uint32_t rim_index;  // into Rim::vertices: the rim vertex it follows
    float weight;
  };
  struct Rim {
    std::vector<RimNeighbours> vertices;
    std::vector<glm::vec3> into_opening;
    std::vector<float> rest_gap;
    std::vector<RimBand> band;
    int passes = 0;
  };
  std::vector<Rim> rims;
  float rim_closing_ratio = 0.0f;
  double mean_distance = 0.0;        // over full-weight vertices, target units
};

// fitted_template: the template registered onto the target (target frame
// and units);
// template_rims: the template's margins, by increasing vertex, or empty.
// \throw InvalidInputError on empty meshes, indices out of range, NaN.
TopologyMapping ComputeTopologyMapping(const Mesh& fitted_template, const Mesh& target,
                                       const TopologyMappingParams& params = {},
                                       std::span<const TemplateRim> template_rims = {});

// Per-vertex template values (deltas: #template vertices) -> per target vertex
// (weight * barycentric interpolation, then smoothed along the rims).
// target_values gets #target vertices.
void MapVertexValues(const TopologyMapping& mapping, std::span<const Triangle> template_triangles,
                     std::span<const glm::vec3> template_values, std::vector<glm::vec3>& target_values);

// Closes the target's rims where the mapped deltas (#target vertices) bring
// their two sides together (TopologyMappingParams::rim_closing_ratio).
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
