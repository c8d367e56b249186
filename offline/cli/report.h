// The --json report of every `facerig` command, one schema for all:
//   {"schema": 1, "command": "build", "version": "0.1.0",
//    "inputs":   [{"role": "template", "path": "..."}, ...],
//    "outputs":  [{"role": "rig", "path": "..."}, ...],
//    "warnings": [{"code": "cannot_blink", "message": "..."}, ...],
//    "timings":  {"load": 0.41, ..., "total": 12.3},
//    "result":   {...what this command found...}}
// Paths as given on the command line; outputs are those written, the report
// not among them; timings in seconds, always with "total".
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "facerig/runtime/rig_warnings.h"

namespace facerig::cli {

inline constexpr int kReportSchema = 1;

// A file a command read or wrote, and what it was to the command.
struct ReportFile {
  std::string role;  // "rig", "template", "target", "landmarks", ...
  std::string path;
};

struct CommandReport {
  explicit CommandReport(std::string command_name, std::vector<ReportFile> input_files = {},
                         std::vector<ReportFile> output_files = {}, std::vector<RigWarning> rig_warnings = {})
      : command(std::move(command_name)),
        inputs(std::move(input_files)),
        outputs(std::move(output_files)),
        warnings(std::move(rig_warnings)) {}

  std::string command;  // the subcommand's name
  std::vector<ReportFile> inputs, outputs;  // entries with an empty path are left out
  std::vector<RigWarning> warnings;
  std::vector<std::pair<std::string, double>> timings;  // stage, seconds
  nlohmann::json result = nlohmann::json::object();
};

// The report with its keys in the order above (the result's sorted).
nlohmann::ordered_json ToJson(const CommandReport& report);

// The report in `path`, written atomically (never a partial file).
// \throw IoError naming the file.
void WriteCommandReport(const std::filesystem::path& path, const CommandReport& report);

}  // namespace facerig::cli
