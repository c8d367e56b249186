// --obj-dir DIR for the `facerig` commands that write a rig: the neutral and
// one OBJ per shape, with their MTL and images, as one output of a set.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "facerig/runtime/io/output_set.h"
#include "facerig/runtime/rig.h"

namespace facerig::cli {

// A file name for a shape: characters other than letters, digits, '_', '-',
// '.' become '_'; ".obj" appended.
std::string ShapeFileName(std::string_view name);

// neutral.obj (positions, UVs, normals) and one OBJ per shape (positions and
// UVs, as ICT-FaceKit's) on the rig's topology, into `folder` (the output
// set's temporary folder for --obj-dir), sharing one materials.mtl and the
// images when the rig has materials. Shapes are written on every core.
void WriteRigObjFolder(const std::filesystem::path& folder, const Rig& rig);

// `path` added to `set` as a folder that is replaced, not merged, and only
// when it holds nothing but what WriteRigObjFolder writes (`option` names it
// in the error). Returns its temporary.
std::filesystem::path AddObjFolderOutput(OutputSet& set, const std::string& path, const char* option = "--obj-dir");

}  // namespace facerig::cli
