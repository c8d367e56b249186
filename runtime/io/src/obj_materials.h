// The MTL files an OBJ names and the images their materials show, read for
// ReadObj (obj.cpp).
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "facerig/runtime/mesh.h"

namespace facerig {

// Fills in the materials `mesh` names (by `usemtl`) from the MTL files
// `mtl_files` (as `mtllib` named them) of the OBJ at `obj_path`, and the
// images their maps name into mesh->images (one per file).
//
// A file that does not exist is not an error: a warning naming it is added
// to `warnings` and the material keeps its colour (or the default white). A
// name leading outside the OBJ's folder (absolute, `..`, a symbolic link),
// a file that is not regular, too large or not a PNG/JPEG of a sane size is
// an IoError naming the MTL file and the statement's line.
void ReadObjMaterials(const std::filesystem::path& obj_path, std::span<const std::string> mtl_files, Mesh* mesh,
                      std::vector<std::string>* warnings);

}  // namespace facerig
