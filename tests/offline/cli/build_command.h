// `facerig build ARGUMENTS...` run in this process, its exit code and stderr captured.
#pragma once

#include <string>
#include <vector>

#include "cli/app.h"
#include "support/command_runner.h"

namespace facerig::test {

inline CommandOutcome RunBuildCommand(const std::vector<std::string>& arguments) {
  std::vector<std::string> all{"build"};
  all.insert(all.end(), arguments.begin(), arguments.end());
  return RunCommand(cli::RunFacerig, all);
}

}  // namespace facerig::test
