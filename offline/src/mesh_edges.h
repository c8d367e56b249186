// Edge structure of a triangle mesh, shared by the offline steps that walk
// it: the boundary (rims of eye and mouth openings, the neck) and each
// vertex's neighbours.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

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

}  // namespace facerig
