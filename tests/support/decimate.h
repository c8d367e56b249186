// Decimated test targets: a mesh simplified by edge collapse
// (meshoptimizer, Debian libmeshoptimizer-dev), as a scan is decimated before
// rigging. Collapses move no vertex, so the decimated mesh's vertices are a
// subset of the original's and any per-vertex truth of the original (its own
// expressions) holds on the decimated mesh at the kept vertices.
#pragma once

#include <cstdint>
#include <vector>

#include "facerig/runtime/mesh.h"

namespace facerig::test {

struct DecimatedMesh {
  // The kept vertices in their original order, the new triangles with their
  // part and material; no corner UVs or normals (a collapse leaves a corner
  // on another vertex's UV seam).
  Mesh mesh;
  std::vector<std::uint32_t> original_vertex;  // mesh vertex i is the original's original_vertex[i]
};

// Each part-and-material group of `mesh` is simplified on its own towards
// `triangle_fraction` of its triangles, with its borders locked: the seams
// between groups stay shared and holes (eye and mouth openings) stay holes.
// Small or closed groups may stop above the fraction.
// \throw std::invalid_argument when the fraction is outside (0, 1] or the mesh is invalid.
DecimatedMesh Decimate(const Mesh& mesh, double triangle_fraction);

}  // namespace facerig::test
