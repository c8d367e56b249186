// libfacerig_offline: the `facerig` command's build, photo, default-head and
// convert run in-process (facerig_cli_commands), their options from JSON,
// their progress and failure through CommandHooks, their report kept per thread.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "boundary.h"
#include "cli/app.h"
#include "cli/common.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/runtime/io/output_set.h"
#include "facerig_offline.h"

namespace facerig::capi {
namespace {

thread_local std::string g_report;

// The options object as command-line arguments after the command's name.
fr_status ToArguments(const char* options_json, std::vector<std::string>* args) {
  const nlohmann::json options = nlohmann::json::parse(options_json ? options_json : "{}", nullptr, false);
  if (options.is_discarded() || !options.is_object()) {
    return Fail(FR_ERROR_INVALID_ARGUMENT, "options_json is not a JSON object");
  }
  std::vector<std::string> inputs;
  for (const auto& [key, value] : options.items()) {
    std::vector<std::string>& into = key == "inputs" ? inputs : *args;
    const std::string name = key.size() == 1 ? "-" + key : "--" + key;
    if (value.is_null() || (value.is_boolean() && !value.get<bool>())) continue;
    if (key != "inputs") into.push_back(name);
    if (value.is_boolean()) continue;
    for (const nlohmann::json& item : value.is_array() ? value : nlohmann::json::array({value})) {
      if (item.is_string()) {
        into.push_back(item.get<std::string>());
      } else if (item.is_number()) {
        into.push_back(item.dump());
      } else {
        return Fail(FR_ERROR_INVALID_ARGUMENT, {"option \"", key, "\" must be a string, a number, true or an array of them"});
      }
    }
  }
  args->insert(args->end(), inputs.begin(), inputs.end());
  return FR_OK;
}

// The status for what the command failed with.
fr_status StatusOf(const std::exception& error) {
  if (const auto* io = dynamic_cast<const IoError*>(&error)) {
    return io->kind() == IoErrorKind::kOpenFailed || io->kind() == IoErrorKind::kWriteFailed ? FR_ERROR_FILE
                                                                                            : FR_ERROR_FORMAT;
  }
  if (dynamic_cast<const std::bad_alloc*>(&error)) return FR_ERROR_OUT_OF_MEMORY;
  return FR_ERROR_FAILED;
}

// A report file of this process and thread, in the temporary folder.
std::filesystem::path ReportPath() {
  static std::atomic<unsigned> counter{0};
  return std::filesystem::temp_directory_path() /
         ("facerig-report-" + std::to_string(getpid()) + "-" + std::to_string(counter++) + ".json");
}

fr_status RunCommand(const char* command, const char* options_json, fr_progress_fn progress, void* user_data) {
  std::vector<std::string> args = {"facerig", command};
  if (const fr_status s = ToArguments(options_json, &args); s != FR_OK) return s;
  // The report: where the caller asked, else a temporary file read back.
  std::filesystem::path report;
  const auto given = std::find(args.begin(), args.end(), "--json");
  const bool temporary_report = given == args.end();
  if (temporary_report) {
    report = ReportPath();
    args.insert(args.begin() + 2, {"--json", report.string()});
  } else if (given + 1 != args.end()) {
    report = *(given + 1);
  }
  CLI::App app("facerig", "facerig");
  cli::CommandBody body;
  cli::AddCommands(app, body);
  std::vector<const char*> argv;
  for (const std::string& arg : args) argv.push_back(arg.c_str());
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::ParseError& error) {
    return Fail(FR_ERROR_INVALID_ARGUMENT, {command, ": ", error.what()});
  }
  fr_status failed = FR_OK;
  bool cancelled = false;
  cli::CommandHooks hooks;
  hooks.failed = [&](const std::exception& error) {
    failed = StatusOf(error);
    Fail(failed, {command, ": ", error.what()});
  };
  if (progress) {
    hooks.progress = [&](const char* stage, std::size_t done, std::size_t total) {
      if (progress(user_data, stage, done, total) != 0) {
        cancelled = true;
        throw Interrupted(SIGINT);  // the command removes its temporaries
      }
    };
  }
  int exit_code = 0;
  try {
    const cli::CommandHooksScope scope(hooks);
    exit_code = body();
  } catch (const Interrupted&) {
    if (!cancelled) throw;
    exit_code = 128 + SIGINT;  // stopped outside the command's own error handling
  }
  std::string text;
  if (exit_code == 0 && !report.empty()) text = ReadInputText(report);
  if (temporary_report) std::filesystem::remove(report);
  if (cancelled) return Fail(FR_ERROR_CANCELLED, {command, ": cancelled by the progress callback; nothing written"});
  if (exit_code != 0) return failed != FR_OK ? failed : Fail(FR_ERROR_FAILED, {command, " failed"});
  g_report = std::move(text);
  return FR_OK;
}

}  // namespace
}  // namespace facerig::capi

using namespace facerig::capi;

extern "C" {

fr_status fr_offline_build(const char* options_json, fr_progress_fn progress, void* user_data) {
  return Guard([&] { return RunCommand("build", options_json, progress, user_data); });
}

fr_status fr_offline_photo(const char* options_json, fr_progress_fn progress, void* user_data) {
  return Guard([&] { return RunCommand("photo", options_json, progress, user_data); });
}

fr_status fr_offline_default_head(const char* options_json, fr_progress_fn progress, void* user_data) {
  return Guard([&] { return RunCommand("default-head", options_json, progress, user_data); });
}

fr_status fr_offline_convert(const char* options_json, fr_progress_fn progress, void* user_data) {
  return Guard([&] { return RunCommand("convert", options_json, progress, user_data); });
}

fr_status fr_offline_report(char* buffer, size_t capacity, size_t* needed) {
  return Guard([&] { return CopyString(g_report, buffer, capacity, needed); });
}

}  // extern "C"
