// `facerig build`: a rig for a new face, end to end, kept out of
// facerig_cli.cpp, which dispatches to it.
#pragma once

#include "cli_options.h"

namespace facerig::cli {

// Adds `build` to the facerig app: --template DIR|RIG --target MESH -o OUT.glb
// [--frig OUT.frig] [--obj-dir DIR] [--mode classic|identity|displacement]
// [--landmarks LM.json] [--json REPORT] [--units mm|cm|m]
// [--template-topology FIT.frig] [--shape-predictor F] [--no-contacts] [--no-eye-fit].
// When it is the parsed subcommand, `body` runs it.
void AddBuildCommand(CLI::App& facerig, CommandBody& body);

}  // namespace facerig::cli
