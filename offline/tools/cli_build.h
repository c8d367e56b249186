// `facerig build`: a rig for a new face, end to end (issue 6), kept out of
// facerig_cli.cpp, which dispatches to it.
#pragma once

namespace facerig::cli {

// facerig build --template DIR|RIG --target MESH -o OUT.glb [--frig OUT.frig]
//               [--obj-dir DIR] [--mode classic|identity|displacement]
//               [--landmarks LM.json] [--json REPORT] [--units mm|cm|m]
//               [--template-topology FIT.frig] [--shape-predictor F]
//               [--no-contacts] [--no-eye-fit]
// argv[0] is the program, argv[1] "build". Returns the exit code (0 ok,
// 1 failure, 2 usage).
int RunBuildCommand(int argc, char** argv);

}  // namespace facerig::cli
