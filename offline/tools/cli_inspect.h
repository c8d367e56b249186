// `facerig inspect`, `facerig convert` and `facerig default-head`.
#pragma once

#include "cli_options.h"

namespace facerig::cli {

// Adds `inspect`: FILE|DIR [folder options].
void AddInspectCommand(CLI::App& facerig, CommandBody& body);

// Adds `convert`: IN OUT [folder options]; formats by extension.
void AddConvertCommand(CLI::App& facerig, CommandBody& body);

// Adds `default-head`: OUT_DIR [--preview DIR [--preview-size PX]].
void AddDefaultHeadCommand(CLI::App& facerig, CommandBody& body);

}  // namespace facerig::cli
