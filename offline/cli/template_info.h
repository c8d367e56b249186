// How the tools tell where a template's descriptor came from (face_template.h).
#pragma once

#include <nlohmann/json.hpp>

#include "facerig/offline/rigging/face_template.h"

namespace facerig {

// One line on stderr: the descriptor's name, source and derived fields.
void PrintTemplateInfo(const FaceTemplateInfo& info);
// {"name", "source", "path", "derived": [...]} for the --json reports.
nlohmann::json TemplateInfoReport(const FaceTemplateInfo& info);

}  // namespace facerig
