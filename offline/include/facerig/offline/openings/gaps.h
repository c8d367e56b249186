// How closed an eye or the mouth is in a pose: the margins found from the
// template's closing expression, and the gap between them (tests and the bench).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/offline/openings/openings.h"
#include "facerig/runtime/mesh.h"

namespace facerig {

// The margins of one opening, found from the template's closing expression:
// upper[i] meets lower[i]. Eyes: lower_margin is the lower lid's margin as a
// polyline (the lid slides as it closes, so the partners mark where the lower
// margin is, not what each upper vertex meets); mouths: empty. width: the
// opening's x extent in the neutral (eye: of the upper lid's moving vertices;
// mouth: of the paired vertices).
struct OpeningMargins {
  OpeningKind kind = OpeningKind::kEye;
  std::vector<std::uint32_t> upper;
  std::vector<std::uint32_t> lower;
  std::vector<std::uint32_t> lower_margin;
  double width = 0.0;
};

// The eyelid margins of one eye, found from the template's blink. upper: the
// upper-lid vertices (moving more than half the blink's largest motion) that
// meet a lower-lid vertex (apart in the neutral, within 10% of the upper
// vertex's motion in the blink); lower: those partners; lower_margin: the
// shortest mesh-edge path (neutral lengths, avoiding the upper lid) from the
// partner of smallest x to that of largest x. Vertices searched:
// [region_first, region_last) (ICT: 0-17038, face and eye sockets, where the
// lid margins are).
// \throw MeshInputError when the blink closes nothing or no mesh path
// joins the lower partners.
OpeningMargins FindEyelidMargins(const Mesh& neutral_mesh, std::span<const glm::vec3> blink,
                                 std::size_t region_first, std::size_t region_last);

// The lip margins, found from the template's closed mouth: ICT's mouthClose is
// made to be added to jawOpen (alone it pushes the lips through each other), so
// open = neutral + jawOpen, closed = neutral + jawOpen + mouthClose. Pairs of a
// vertex that mouthClose moves (more than 0.3 of its largest motion in the
// region) and the vertex it meets: apart in the open pose (by more than 0.3 of
// that motion), within 10% of their open distance in the closed pose. Each
// pair once, upper = the higher of the two in the open pose. Vertices searched:
// [region_first, region_last) (ICT: the face, 0-9408).
// \throw MeshInputError on a vertex count mismatch or when the lips meet nowhere.
OpeningMargins FindLipMargins(std::span<const glm::vec3> neutral, std::span<const glm::vec3> open,
                              std::span<const glm::vec3> closed, std::size_t region_first,
                              std::size_t region_last);

// How closed an opening is on a (transferred) mesh, over its width.
// Eyes: for the upper margin vertices whose x lies within the lower margin's
// x extent in that pose (the lid corners, where the lower polyline ends, are
// left out), the distance to the lower margin polyline, and crossing below it
// (along y). Mouths: the distance of each pair, and lower above upper (y).
struct OpeningGap {
  double mean_gap = 0.0;      // mean distance
  double max_gap = 0.0;       // largest such distance
  double max_crossing = 0.0;  // deepest crossing, >= 0
  std::size_t measured_vertices = 0;  // upper margin vertices (eyes) or pairs (mouths) measured
};
OpeningGap MeasureOpeningGap(std::span<const glm::vec3> positions, const OpeningMargins& margins);

}  // namespace facerig
