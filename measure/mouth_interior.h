// How clean a built rig's mouth is when it opens, on the built-in head (its
// features name its lips and mouth corners): the curtain (the upper lip's
// inner side and the palate following the jaw) and the fold under the lower
// lip, both in jawOpen at weight 1. The tests and `facerig-bench mouth`
// measure with it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/offline/default_head/default_head.h"
#include "facerig/runtime/rig.h"

namespace facerig {

// The upper mouth: vertices above the head's lip seam (its mouth corners'
// height), between its mouth corners, that its own jawOpen leaves (less
// than a tenth of its lower lip's median motion): the upper lip and its
// inner side (skin), the palate of the mouth sack ("mouth_inner"); not its
// teeth or tongue. A vertex follows the jaw when the built jawOpen moves it
// by more than half the built lower lip's median motion.
struct MouthCurtain {
  std::size_t upper_vertices = 0;   // the upper mouth, skin and sack
  std::size_t skin_on_jaw = 0;      // of its skin, following the jaw
  std::size_t sack_on_jaw = 0;      // of its sack, following the jaw
  // The largest motion of an upper-mouth vertex over the built lower lip's
  // median motion: 0 still, 1 with the jaw.
  float worst_ratio = 0.0f;
  float lower_lip_motion = 0.0f;    // the built jawOpen's, rig units
};

// The fold: the largest change, from the neutral to jawOpen at weight 1, of
// the angle between two neighbouring triangles of the skin under the lower
// lip (below its vermilion border's lowest point, down to half a mouth width
// below it, between the mouth corners, facing forward: normal within 60
// degrees of the face's +z). The lip itself is left out: its margin rolls
// as it stretches (ICT-FaceKit's own jawOpen turns it by 14 degrees).
struct LipFold {
  float degrees = 0.0f;
  glm::vec3 at{0.0f};
  float below_lip = 0.0f;   // how far the worst edge lies below the lower lip's border, rig units
  std::size_t edges = 0;    // edges measured
};

// head: the built-in head with its own jawOpen; built: a rig on the head's
// vertices (same count and order) with jawOpen. \throw InvalidInputError
// when either lacks jawOpen or the vertex counts differ.
MouthCurtain MeasureMouthCurtain(const Rig& head, const Rig& built, const DefaultHeadFeatures& features);
LipFold MeasureLipFold(const Rig& rig, const DefaultHeadFeatures& features);
// The same on any face with y up and z forward: its two mouth corner
// vertices, a vertex at the bottom of its lower lip's vermilion border
// (dlib's landmark 57), its skin the vertices below skin_vertex_count
// (ICT-FaceKit: its face, head and neck).
LipFold MeasureLipFold(const Rig& rig, std::array<std::uint32_t, 2> mouth_corners, std::uint32_t lower_lip_bottom,
                       std::uint32_t skin_vertex_count);

// The rig's neutral plus one shape at full weight. \throw InvalidInputError
// when it has no such shape.
std::vector<glm::vec3> PoseWithShape(const Rig& rig, std::string_view name);

}  // namespace facerig
