// The template `facerig photo` fits to a photograph: the --template rig or
// folder, or the built-in head, with its surface (UVs, materials), its
// descriptor and, in a template folder, its identity meshes.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/offline/rigging/face_template.h"
#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/photo/fit.h"
#include "facerig/offline/rigging/standard_shapes.h"
#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"

namespace facerig::cli {

struct PhotoTemplate {
  Rig rig;
  Mesh surface;  // on the rig's vertices, its triangle t the rig's triangle t (MakePhotoRig)
  FaceTemplateInfo info;
  std::vector<std::vector<glm::vec3>> identities;  // identityNNN.obj of a template folder
  std::string source;       // the file or folder read; empty for a head made in memory
  std::string description;  // for messages: the path, or "the built-in head (...)"
  bool built_in = false;
  // The template had no tongueOut: made from this part of it (tongue_out.h);
  // empty when it had one, or no tongue.
  std::string tongue_out_synthesised_from;
};

// The built-in head as the player finds it: installed beside the executable
// (BINDIR/../share/facerig/default_head.frig), else the build tree's; empty
// when neither exists.
std::filesystem::path BuiltInHeadPath();

// `template_path` (a rig or a template folder), or the built-in head when it
// is empty (made in memory when no file of it exists). Viseme targets that
// `naming` bakes again are dropped (standard_shapes.h); a template with a
// tongue but no tongueOut gets one, as `facerig build` gives it.
// \throw IoError as the readers; InvalidInputError as LoadIdentityMeshes.
PhotoTemplate LoadPhotoTemplate(const std::string& template_path, const StandardShapesOptions& naming);

// The template's face model: its landmark vertices (the descriptor's, or
// detected on its neutral), identity modes and expressions, calibrated
// against dlib on a render of the neutral.
PhotoFaceModel BuildPhotoModel(PhotoTemplate& photo_template, LandmarkDetector& detector);

}  // namespace facerig::cli
