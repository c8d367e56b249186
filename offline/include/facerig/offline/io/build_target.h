// Loading the target of `facerig build` as a BuildTarget: the rig data the
// build works on and the mesh its file has, UVs, parts and materials included.
#pragma once

#include <filesystem>

#include "facerig/offline/rigging/rig_build.h"
#include "facerig/runtime/rig.h"

namespace facerig {

// .obj and .glb/.gltf: the rig as LoadRig reads it and the file's Mesh
// (ReadObj grouped by part, ReadGltfMesh); any other rig or a template folder
// (LoadRigOrTemplateFolder): its neutral as the mesh. `units` overrides the
// file's units when not kUnknown. Throws IoError.
BuildTarget LoadBuildTarget(const std::filesystem::path& path, Units units = Units::kUnknown);

}  // namespace facerig
