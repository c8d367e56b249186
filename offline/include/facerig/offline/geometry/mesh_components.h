// Connected parts of a mesh, and its main surface: its large connected parts. An artist's head
// has separate eyeballs, teeth, lashes and transparent layers around the
// eyes; registration, eye openings and lid margins are about the skin.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/runtime/rig.h"

namespace facerig {

// Connected parts of a triangle mesh: part index per vertex (vertices used by
// no triangle get parts of their own). Returns the number of parts.
std::size_t ConnectedComponents(std::size_t vertex_count, std::span<const Triangle> triangles,
                                std::vector<std::uint32_t>& component_of_vertex);

// The triangles of the connected parts whose area is at least `min_fraction`
// of the largest part's; `left_out` (if given) counts the parts dropped.
std::vector<Triangle> LargePartTriangles(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                                         double min_fraction, std::size_t* left_out = nullptr);

}  // namespace facerig
