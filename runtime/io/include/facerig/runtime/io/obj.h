// Wavefront OBJ reading and writing.
//
// Reading: `v`, `vt`, `vn`, `f` (triangles, quads and n-gons, fan-triangulated),
// the forms v, v/vt, v//vn and v/vt/vn, negative (relative) indices, `g`, `o`,
// `usemtl` and `mtllib`, into a Mesh (mesh.h). ReadObj reads the MTL files
// and their images (mtl.h); ParseObj opens no file and names the materials only.
//
// Writing: positions, normals and UVs per vertex; with materials, an MTL file
// and the images beside the OBJ.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "facerig/runtime/io/mtl.h"
#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {

struct ObjStats {
  std::size_t polygon_count = 0;  // faces in the file before triangulation
  std::vector<std::string> mtl_files{};  // as `mtllib` names them, in order
  // Short messages naming a file ReadObj did not find (an MTL, an image) or a
  // material no MTL defines; what they name keeps its default or colour.
  std::vector<std::string> warnings{};
};

// The mesh in the file's triangle order: per-corner UVs and normals; parts by
// material when the file has any `usemtl` (then one material per name), else
// by group; triangles outside any get the part "default".
// Throws IoError with the path and 1-based line on malformed input.
// ParseObj's materials have a name only (the default white, opaque).
Mesh ParseObj(std::string_view text, const std::string& path_for_errors, ObjStats* stats = nullptr);
// As ParseObj, then the materials from the `mtllib` files, each resolved
// inside the OBJ's folder, and the images of their maps (mesh.images, one per
// file, each resolved inside its MTL's folder). A missing MTL or image file is
// a warning in `stats`, not an error; a name leading outside the folder, a
// file that is not regular or too large, or a broken image is an IoError.
Mesh ReadObj(const std::filesystem::path& path, ObjStats* stats = nullptr);

// Writes a mesh with per-vertex positions (and normals, UVs if non-empty), one
// `usemtl` per part naming the part. Atomic (temporary file + rename).
void WriteObj(const std::filesystem::path& path, std::span<const glm::vec3> positions,
              std::span<const glm::vec3> normals, std::span<const glm::vec2> uvs,
              std::span<const Triangle> triangles, std::span<const Part> parts);
// The same with `mtllib mtl.mtl_file` and, per part, `usemtl` naming its
// material (Part::material, by mtl.material_names); a part without one gets
// `usemtl default` (with '_' appended while a material has that name), which
// reads back as the default material. The MTL is
// written separately (WriteMtl), so that a folder of OBJs can share one.
// An empty mtl.mtl_file (a rig without materials) writes as the overload above.
void WriteObj(const std::filesystem::path& path, std::span<const glm::vec3> positions,
              std::span<const glm::vec3> normals, std::span<const glm::vec2> uvs,
              std::span<const Triangle> triangles, std::span<const Part> parts, const MtlReference& mtl);
// The faces of one topology formatted once, for writing many OBJs of it (a
// rig's neutral and each of its shapes): Write makes the same file as
// WriteObj with these triangles, parts and MTL. Write is const and may run on
// several threads at once.
class ObjTopologyWriter {
 public:
  // `path_for_errors`: named when a part's material is out of range.
  ObjTopologyWriter(std::span<const Triangle> triangles, std::span<const Part> parts, const MtlReference& mtl,
                    bool with_normals, bool with_uvs, const std::string& path_for_errors);
  // \pre normals and uvs non-empty exactly as the constructor said.
  void Write(const std::filesystem::path& path, std::span<const glm::vec3> positions,
             std::span<const glm::vec3> normals, std::span<const glm::vec2> uvs) const;

 private:
  std::string header_;
  std::string faces_;
};

// The rig's neutral mesh. With materials, also <stem>.mtl and the images
// beside it (WriteMtl).
void WriteObj(const std::filesystem::path& path, const Rig& rig);
// The rig's neutral mesh using an MTL already written (WriteMtl).
void WriteObj(const std::filesystem::path& path, const Rig& rig, const MtlReference& mtl);

}  // namespace facerig
