// Wavefront OBJ reading and writing.
//
// Reading: `v`, `vt`, `vn`, `f` (triangles, quads and n-gons, fan-triangulated),
// the forms v, v/vt, v//vn and v/vt/vn, negative (relative) indices, `g`, `o`
// and `usemtl`, into a Mesh (mesh.h).
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {

struct ObjStats {
  std::size_t polygon_count = 0;  // faces in the file before triangulation
};

// The mesh in the file's triangle order: per-corner UVs and normals; parts by
// material when the file has any `usemtl` (then one material per name), else
// by group; triangles outside any get the part "default".
// Throws IoError with the path and 1-based line on malformed input.
Mesh ParseObj(std::string_view text, const std::string& path_for_errors, ObjStats* stats = nullptr);
Mesh ReadObj(const std::filesystem::path& path, ObjStats* stats = nullptr);

// Writes a mesh with per-vertex positions (and normals, UVs if non-empty), one
// `usemtl` per part. Atomic (temporary file + rename).
void WriteObj(const std::filesystem::path& path, std::span<const glm::vec3> positions,
              std::span<const glm::vec3> normals, std::span<const glm::vec2> uvs,
              std::span<const Triangle> triangles, std::span<const Part> parts);
// The rig's neutral mesh.
void WriteObj(const std::filesystem::path& path, const Rig& rig);

}  // namespace facerig
