#include "support/command_runner.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include <catch2/catch.hpp>

#include "support/test_meshes.h"

namespace facerig::test {

CommandOutcome RunCommand(const std::function<int(int, char**)>& command, const std::vector<std::string>& arguments) {
  std::vector<std::string> storage{"facerig"};
  storage.insert(storage.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& s : storage) argv.push_back(s.data());
  argv.push_back(nullptr);

  CommandOutcome outcome;
  outcome.error_output = CaptureOutput(stderr, "command_stderr", [&] {
    outcome.exit_code = command(static_cast<int>(storage.size()), argv.data());
  });
  return outcome;
}

std::string CaptureOutput(std::FILE* stream, const std::string& name, const std::function<void()>& body) {
  const std::filesystem::path capture = OutputPath(name + "_" + std::to_string(getpid()) + ".txt");
  std::cout.flush();
  std::fflush(stream);
  const int saved = dup(fileno(stream));
  std::FILE* file = std::fopen(capture.c_str(), "w");
  dup2(fileno(file), fileno(stream));
  body();
  std::cout.flush();
  std::fflush(stream);
  dup2(saved, fileno(stream));
  close(saved);
  std::fclose(file);
  std::ostringstream text;
  text << std::ifstream(capture).rdbuf();
  return text.str();
}

int RunShell(const std::string& command, std::string* output) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  REQUIRE(pipe != nullptr);
  char buffer[512];
  while (std::fgets(buffer, sizeof(buffer), pipe) != nullptr) *output += buffer;
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::size_t CountOccurrences(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

bool NoTemporaryFilesIn(const std::filesystem::path& dir) {
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().filename().string().find(".tmp") != std::string::npos) return false;
  }
  return true;
}

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace facerig::test
