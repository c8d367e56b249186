// The main surface of a mesh: its large connected parts. An artist's head
// has separate eyeballs, teeth, lashes and transparent layers around the
// eyes; registration, eye openings and lid margins are about the skin.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/runtime/rig.h"

namespace facerig {

// The triangles of the connected parts whose area is at least `min_fraction`
// of the largest part's; `left_out` (if given) counts the parts dropped.
std::vector<Triangle> LargePartTriangles(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                                         double min_fraction, std::size_t* left_out = nullptr);

}  // namespace facerig
