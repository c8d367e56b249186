// Edge structure of a triangle mesh, shared by the offline steps that walk
// it: the boundary (rims of eye and mouth openings, the neck) and each
// vertex's neighbours.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/runtime/rig.h"

namespace facerig {

// A triangle side used by no other triangle: from a to b as its triangle
// winds, and the triangle's third vertex.
struct BoundarySide {
  std::uint32_t a;
  std::uint32_t b;
  std::uint32_t opposite;
};
std::vector<BoundarySide> BoundarySides(std::span<const Triangle> triangles);

// Each vertex's neighbours along triangle edges, without duplicates, as
// compressed rows: vertex v's are neighbours[begin[v] .. begin[v + 1]).
void VertexNeighbours(std::size_t vertex_count, std::span<const Triangle> triangles,
                      std::vector<std::uint32_t>& begin, std::vector<std::uint32_t>& neighbours);

// The vertices within reach of a set of sources along mesh edges (lengths
// at `positions`; multi-source Dijkstra): each vertex goes to its nearest
// source and is kept when nearer than that source's reach (reach[i] for
// sources[i]), in order of distance, the sources first.
struct EdgeReach {
  std::uint32_t vertex;
  float distance;
  std::uint32_t source;  // index into sources
};
std::vector<EdgeReach> VerticesWithinReach(std::span<const glm::vec3> positions,
                                           const std::vector<std::uint32_t>& neighbour_begin,
                                           const std::vector<std::uint32_t>& neighbours,
                                           std::span<const std::uint32_t> sources, std::span<const float> reach);

}  // namespace facerig
