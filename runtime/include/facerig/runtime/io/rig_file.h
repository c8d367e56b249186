// Loading and saving rigs by path: the format comes from the extension, or a
// directory is imported as a template folder.
#pragma once

#include <filesystem>

#include "facerig/runtime/io/template_folder.h"
#include "facerig/runtime/rig.h"

namespace facerig {

// A directory (template folder of OBJs), .obj (neutral only, no shapes),
// .glb, .gltf or .frig. Throws IoError.
Rig LoadRig(const std::filesystem::path& path, const TemplateImportOptions& folder_options = {});
// .obj (neutral only), .glb, .gltf or .frig. Throws IoError.
void SaveRig(const std::filesystem::path& path, const Rig& rig);

}  // namespace facerig
