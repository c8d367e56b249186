// The one mesh type: what readers produce and every offline algorithm takes.
//
// Attributes that differ across a seam (UVs, normals) are per triangle corner,
// as files store them; the runtime Rig is per vertex (rig_builder.h converts).
// Parts and materials are per triangle, indices into the mesh's own tables.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "facerig/runtime/material.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {

struct Mesh {
  std::vector<glm::vec3> positions{};
  std::vector<Triangle> triangles{};
  std::vector<glm::vec2> corner_uvs{};      // empty, or 3 per triangle
  std::vector<glm::vec3> corner_normals{};  // empty, or 3 per triangle
  // Empty (the whole mesh is one part), or one index into part_names per triangle.
  std::vector<std::uint32_t> triangle_parts{};
  std::vector<std::string> part_names{};
  // Empty (no material), or one index into materials per triangle.
  std::vector<std::uint32_t> triangle_materials{};
  std::vector<Material> materials{};
  std::vector<EncodedImage> images{};  // what the materials show

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t triangle_count() const { return triangles.size(); }
  // True when every index and array size is consistent and every coordinate
  // finite; `problem` (if given) names the first offending element,
  // e.g. "triangle 12: vertex index 900 >= 850".
  bool Validate(std::string* problem = nullptr) const;
};

// Per-vertex attributes of a mesh (the Rig's layout): where a vertex has
// several corner values (a seam), the first corner in triangle order wins.
struct VertexAttributes {
  std::vector<glm::vec3> normals;  // empty when the mesh has none
  std::vector<glm::vec2> uvs;      // empty when the mesh has none
  std::size_t uv_seam_vertices = 0;      // vertices given more than one UV
  std::size_t normal_seam_vertices = 0;  // vertices given more than one normal
};
VertexAttributes PerVertexAttributes(const Mesh& mesh);

// The neutral mesh of a rig: positions, triangles, parts (one name per part
// range) and its per-vertex UVs and normals spread to the corners.
Mesh NeutralMesh(const Rig& rig);
Mesh NeutralMesh(const RawRig& rig);

// The same mesh with its triangles (and their corners, parts and materials)
// grouped by part and material as ToRawRig orders them: parts in order of
// first appearance, a part's materials likewise, triangles in order within
// each. Its triangle t is then triangle t of ToRawRig(mesh), so its corner
// data lines up with a rig built from it. A mesh with materials but no parts
// becomes one part "mesh".
Mesh GroupedByPart(const Mesh& mesh);

// The rig layout of a mesh (no shapes): per-vertex attributes as above,
// triangles grouped (GroupedByPart) so that each part and material is one
// range (a part with two materials becomes two parts of the same name), and
// the materials and images.
RawRig ToRawRig(const Mesh& mesh);

}  // namespace facerig
