// What ComputeTopologyMapping (topology_mapping.h) takes and returns,
// without the search: for headers that only pass these on (rig_build.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/offline/openings/openings.h"

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

}  // namespace facerig
