// Runs a `facerig` subcommand in-process (tools/cli_*.h) with its stderr
// captured, so tests can check exit codes and messages; runs a program
// through the shell with its output captured.
#pragma once

#include <cstdio>
#include <filesystem>
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

// Calls body() with `stream` (stdout or stderr) sent to a file named after
// `name`; returns what body printed there.
std::string CaptureOutput(std::FILE* stream, const std::string& name, const std::function<void()>& body);

// Runs `command` through the shell, appends its stdout and stderr to *output;
// returns its exit code (-1 when it did not exit normally).
int RunShell(const std::string& command, std::string* output);

// Whether no file in `dir` is a writer's temporary (a name with ".tmp" in it).
bool NoTemporaryFilesIn(const std::filesystem::path& dir);

// Whether `part` occurs in `text`.
bool Contains(const std::string& text, const std::string& part);

// How many times `part` occurs in `text` (overlaps counted): a warning printed once is 1.
std::size_t CountOccurrences(const std::string& text, const std::string& part);

}  // namespace facerig::test
