// facerig: inspect, convert, register and build rigs. `facerig --help` lists
// the subcommands (tools/cli_app.cpp); each runs from tools/cli_*.cpp.
#include "cli/app.h"

int main(int argc, char** argv) { return facerig::cli::RunFacerig(argc, argv); }
