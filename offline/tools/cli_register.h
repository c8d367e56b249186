// `facerig landmarks` and `facerig register` (registration, issue 5): kept
// out of facerig_cli.cpp, which dispatches to them.
#pragma once

namespace facerig::cli {

// facerig landmarks MESH -o LM.json [--debug-png P] [--json REPORT] [--shape-predictor F]
// argv[0] is the program, argv[1] "landmarks". Returns the exit code
// (0 ok, 1 failure, 2 usage).
int RunLandmarksCommand(int argc, char** argv);

// facerig register --template DIR|RIG --target MESH -o FITTED.obj
//                  [--landmarks LM.json] [--json REPORT] [--shape-predictor F]
int RunRegisterCommand(int argc, char** argv);

}  // namespace facerig::cli
