// The built-in head's template descriptor (face_template.h), written beside
// the generated head so that a build with it as the template reads it there.
#include "facerig/offline/default_head/default_head.h"
#include "facerig/offline/rigging/face_template.h"
#include "facerig/runtime/files/atomic_file.h"

namespace facerig {

FaceTemplateInfo DefaultHeadTemplateInfo(const Rig& head) {
  FaceTemplateInfo info = DeriveFaceTemplateInfo(head);
  info.name = "default-head";
  // The head's own part groups are authoritative here, not guesses; the
  // landmarks and rims stay "derive" (found on the mesh when building).
  info.derived.clear();
  for (const char* part : {"eye_white_L", "eye_white_R", "iris_L", "iris_R", "pupil_L", "pupil_R", "teeth_upper",
                           "teeth_lower"}) {
    if (info.FindPart(part)) info.rigid_parts.emplace_back(part);
  }
  return info;
}

std::filesystem::path WriteDefaultHeadTemplateInfo(const Rig& head, const std::filesystem::path& directory) {
  const std::filesystem::path path = directory / "default_head.template.json";
  WriteFileAtomically(path, FaceTemplateInfoToJson(DefaultHeadTemplateInfo(head)));  // checks every write and the close
  return path;
}

}  // namespace facerig
