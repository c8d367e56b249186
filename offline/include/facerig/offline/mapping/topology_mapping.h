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
#include "facerig/offline/mapping/topology_mapping_types.h"
#include "facerig/offline/openings/openings.h"
#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {

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
