#include "support/command_runner.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "support/test_meshes.h"

namespace facerig::test {

CommandOutcome RunCommand(const std::function<int(int, char**)>& command, const std::vector<std::string>& arguments) {
  std::vector<std::string> storage{"facerig"};
  storage.insert(storage.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& s : storage) argv.push_back(s.data());
  argv.push_back(nullptr);

  // stderr into a file for the duration of the call.
  const std::filesystem::path capture = OutputPath("command_stderr_" + std::to_string(getpid()) + ".txt");
  std::fflush(stderr);
  const int saved = dup(fileno(stderr));
  std::FILE* file = std::fopen(capture.c_str(), "w");
  dup2(fileno(file), fileno(stderr));
  CommandOutcome outcome;
  outcome.exit_code = command(static_cast<int>(storage.size()), argv.data());
  std::fflush(stderr);
  dup2(saved, fileno(stderr));
  close(saved);
  std::fclose(file);
  std::ostringstream text;
  text << std::ifstream(capture).rdbuf();
  outcome.error_output = text.str();
  return outcome;
}

}  // namespace facerig::test
