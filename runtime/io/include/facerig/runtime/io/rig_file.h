// Loading and saving rigs by path, the format from the extension. Part of
// facerig::runtime_io (tinygltf for glTF); a folder of OBJs (a template) is
// imported by facerig::offline (facerig/offline/io/template_folder.h).
#pragma once

#include <filesystem>

#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"

namespace facerig {

// What an .obj file does not say about itself.
struct ObjLoadOptions {
  Units units = Units::kUnknown;
  UpAxis up_axis = UpAxis::kY;
};

// .obj (neutral only, no shapes), .glb, .gltf or .frig. Throws IoError. An
// OBJ is dressed in its own surface (RigWithSurface): vertices are copied at
// UV seams, after the file's own, so that every corner keeps its UV, as in a
// GLB written from it.
Rig LoadRig(const std::filesystem::path& path, const ObjLoadOptions& obj_options = {});
// The rig of an OBJ's mesh on the file's own vertices, one UV per vertex
// (ToRawRig; all normals recomputed when some vertex has none): what a build
// registers onto. Throws IoError(kInvalidRig) naming `path`.
Rig RigFromObjMesh(const Mesh& mesh, const std::filesystem::path& path, const ObjLoadOptions& obj_options = {});
// .obj (neutral only), .glb, .gltf or .frig. Throws IoError.
void SaveRig(const std::filesystem::path& path, const Rig& rig);

}  // namespace facerig
