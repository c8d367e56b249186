// Runs a `facerig` subcommand in-process (tools/cli_*.h) with its stderr
// captured, so tests can check exit codes and messages.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace facerig::test {

struct CommandOutcome {
  int exit_code = -1;
  std::string error_output;  // what the command printed on stderr
};

// Calls command(argc, argv) with argv = {"facerig", arguments...}.
CommandOutcome RunCommand(const std::function<int(int, char**)>& command, const std::vector<std::string>& arguments);

}  // namespace facerig::test
