// The `facerig` command line: one CLI::App with a subcommand per tool.
#pragma once

#include "cli/options.h"

namespace facerig::cli {

// Adds every subcommand to `app`; parsing a command line sets `body` to run it.
void AddCommands(CLI::App& app, CommandBody& body);

// Parses argv (argv[0] the program, argv[1] the subcommand) and runs the
// subcommand. Returns the exit code: 0 ok (and after --help, --version),
// 1 failure, 2 a bad command line.
int RunFacerig(int argc, char** argv);

}  // namespace facerig::cli
