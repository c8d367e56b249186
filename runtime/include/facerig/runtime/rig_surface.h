// A rig dressed with the surface of the mesh it was built from: that mesh's
// corner UVs (split at seams) and its materials and images.
#pragma once

#include <optional>
#include <string>

#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"

namespace facerig {

// `surface` is a mesh on the rig's vertices whose triangle t is the rig's
// triangle t (GroupedByPart of the mesh the rig was built from). Where a
// vertex has corners with different UVs (a seam), copies of it are appended
// after the rig's vertices, each with the vertex's normal and shape deltas, so
// vertex v < rig.vertex_count() is still the rig's vertex v. Parts are split
// into runs of one material, each run naming its material. Without materials
// and seams the result is the rig as it is (with the surface's UVs).
// Returns nullopt, with `problem` filled in, when `surface` does not fit.
std::optional<Rig> RigWithSurface(const Rig& rig, const Mesh& surface, std::string* problem = nullptr);

}  // namespace facerig
