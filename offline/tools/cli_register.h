// `facerig landmarks` and `facerig register`: kept out of facerig_cli.cpp,
// which dispatches to them.
#pragma once

#include "cli_options.h"

namespace facerig::cli {

// Adds `landmarks`: MESH -o LM.json [--debug-png P] [--json REPORT] [--shape-predictor F].
void AddLandmarksCommand(CLI::App& facerig, CommandBody& body);

// Adds `register`: --template DIR|RIG --target MESH -o FITTED.obj
// [--landmarks LM.json] [--json REPORT] [--shape-predictor F].
void AddRegisterCommand(CLI::App& facerig, CommandBody& body);

}  // namespace facerig::cli
