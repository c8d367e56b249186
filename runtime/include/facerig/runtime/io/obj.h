// Wavefront OBJ reading and writing.
//
// Reading: `v`, `vt`, `vn`, `f` (triangles, quads and n-gons, fan-triangulated),
// the forms v, v/vt, v//vn and v/vt/vn, negative (relative) indices, `g`, `o`
// and `usemtl`. Parts: by material when the file has any `usemtl`, otherwise by
// group (`g`/`o`); triangles are reordered stably so each part is one range.
// UVs and normals are per vertex (the facerig rig is per vertex): where a
// vertex has several (a UV seam), the first one seen wins and the seam is counted.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/rig.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {

struct ObjMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // empty, or one per vertex
  std::vector<glm::vec2> uvs;      // empty, or one per vertex
  std::vector<Triangle> triangles;
  std::vector<RawPart> parts;      // tiles the triangles in order
  std::size_t polygon_count = 0;   // faces in the file before triangulation
  std::size_t uv_seam_vertices = 0;      // vertices given more than one UV
  std::size_t normal_seam_vertices = 0;  // vertices given more than one normal
};

// Throws IoError with the path and 1-based line on malformed input.
ObjMesh ParseObj(std::string_view text, const std::string& path_for_errors);
ObjMesh ReadObj(const std::filesystem::path& path);

// Writes a mesh with per-vertex positions (and normals, UVs if non-empty), one
// `usemtl` per part. Atomic (temporary file + rename).
void WriteObj(const std::filesystem::path& path, std::span<const glm::vec3> positions,
              std::span<const glm::vec3> normals, std::span<const glm::vec2> uvs,
              std::span<const Triangle> triangles, std::span<const Part> parts);
// The rig's neutral mesh.
void WriteObj(const std::filesystem::path& path, const Rig& rig);

}  // namespace facerig
