// The two sides of the mouth, for topology mapping: the target's vertices
// in and around the mouth search only the template's triangles on their own
// side. Without it, where a template's lips touch at rest, a target's upper
// lip takes the motion of the template's lower lip, and a target's palate
// (its mouth sack, nearer to the template's tongue than to its gums) follows
// the jaw: a curtain hangs across the opened mouth.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/offline/geometry/similarity.h"
#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"

namespace facerig {

enum class MouthSide : std::uint8_t { kEither = 0, kUpper, kLower };

struct MouthSides {
  // Per template triangle: kLower where the template's jawOpen carries it
  // (at least two of its vertices move more than half as much as a rigid
  // jaw turn fitted to its lower lip would), else kUpper. Empty: no sides
  // (the template has no jawOpen or mouthClose, its lips meet nowhere, or
  // the target's mouth is not a hole in its mesh).
  std::vector<MouthSide> template_triangle;
  // Per target vertex inside the mouth zone: on a part lying mostly in the
  // zone and hanging from the rim (a mouth sack), the side of the lip its
  // own surface leads to (the rim's chains); elsewhere (the face's skin, a
  // tongue) above or below the lip seam; kEither outside the zone.
  std::vector<MouthSide> target_vertex;
  std::size_t upper_vertices = 0;
  std::size_t lower_vertices = 0;
};

// The mouth zone, as fractions of the seam's width (corner to corner).
struct MouthSideParams {
  float zone_above = 0.6f;   // up to the nose: the palate of a deep mouth sack
  float zone_below = 0.45f;  // the mouth floor, not the underside of the chin
  float zone_behind = 1.2f;  // from the seam's front to the back of the mouth
  float zone_front = 0.1f;   // the lips' outer side in front of the seam
  float rim_front = 0.03f;    // sides only behind the rim (inner lips, mouth sack), not on the outer lips
  // A zone vertex of a part lying mostly in the zone and hanging from the
  // rim (a mouth sack) takes the side of the lip its surface leads to
  // (false: by its height, the previous rule), searched up to chain_reach x
  // the seam's width along it (the back of a deep sack); the lower side only
  // when the lower lip is nearer than lower_share of the upper's distance:
  // where a sack's roof and floor meet, both are about as far, and the back
  // of the mouth stays with the skull (0.6-0.9 give the same sides on the
  // built-in head; 1.0 gives the jaw 2 of its palate's vertices).
  bool along_surface = true;
  float chain_reach = 3.0f;
  float lower_share = 0.8f;
};

// template_rig: the template (its frame: y up, x across the face, z
// forward), with ARKit jawOpen and mouthClose; fitted: the template fitted
// onto the target (target frame); to_template: target frame -> template
// frame; region_vertex_count: the template's face region, where the lip
// seam is searched (FindLipMargins). Where the target's mouth is a hole in
// its mesh, its rim's upper and lower chains give the seam and their own
// vertices' sides.
MouthSides FindMouthSides(const Rig& template_rig, std::span<const glm::vec3> fitted,
                          const SimilarityTransform& to_template, std::span<const glm::vec3> target_positions,
                          std::span<const Triangle> target_triangles, std::uint32_t region_vertex_count,
                          const MouthSideParams& params = {});

}  // namespace facerig
