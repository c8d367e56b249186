// Helpers shared by the `facerig` subcommands (tools/cli_*.cpp): adding a
// subcommand and its common options, mesh loading for targets, outputs
// written as one set with their JSON report (cli_report.h), a progress bar on stderr, timing.
#pragma once

#include <chrono>
#include <cstddef>
#include <exception>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string>

#include "cli/options.h"  // SecondsSince
#include "cli/report.h"
#include "facerig/offline/io/template_folder.h"
#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/runtime/io/output_set.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig::cli {

// A subcommand and the options its flags fill in.
template <typename Options>
struct Subcommand {
  CLI::App* app;
  std::shared_ptr<Options> options;
};

// Adds the subcommand `name` with its --help footer; once the whole command
// line has parsed, `body` becomes run(options). The caller adds the flags.
template <typename Options>
Subcommand<Options> AddSubcommand(CLI::App& facerig, CommandBody& body, const char* name, const char* description,
                                  const char* footer, int (*run)(const Options&)) {
  CLI::App* app = facerig.add_subcommand(name, description);
  app->footer(footer);
  auto options = std::make_shared<Options>();
  app->callback([&body, options, run] { body = [options, run] { return run(*options); }; });
  return {app, options};
}

// -o OUTPUT (required) and --json REPORT: the file a command makes and its report.
void AddOutputOptions(CLI::App& app, std::string& output, std::string& report_path, const std::string& output_help);

// --shape-predictor FILE into `params` (the dlib 68-point model).
CLI::Option* AddShapePredictorOption(CLI::App& app, LandmarkParams& params);

// A mesh to work on, as raw data: .obj (positions, UVs, parts, normals kept)
// or any rig format LoadRig reads (.frig, .glb, .gltf, a template folder).
// `units` overrides the file's units when not kUnknown.
RawRig LoadMeshForEditing(const std::filesystem::path& path, Units units = Units::kUnknown);

// A template rig (a file, or a folder of OBJs imported through the cache in
// DefaultTemplateCacheFolder(), template_cache.h; a line on stderr says
// whether the cache was used). `report`, when given, gets the folder's import report.
Rig LoadTemplateRig(const std::filesystem::path& path, TemplateImportReport* report = nullptr);

// Writes a command's outputs as one set (output_set.h): `write` adds each to
// `set` and writes it under the temporary name Add() returns; then all are
// renamed into place together. On any error, or SIGINT / SIGTERM between
// writes (Interrupted), the temporaries go and the previous outputs stay;
// errors name the final paths and say the previous outputs are unchanged.
void WriteOutputSet(const std::function<void(OutputSet& set)>& write);

// `path` added to `set` as a file: its temporary, or an empty path when
// `path` is empty (an output not asked for).
std::filesystem::path AddOptionalFile(OutputSet& set, const std::string& path);

// Writes an output that may bring files beside it (an OBJ's MTL and images):
// `write(path)` writes it at `path`, of `final_path`'s name, in a scratch
// folder beside `final_path`; each file it made there becomes an output of
// `set` under its name beside `final_path`. Returns `final_path`'s temporary.
std::filesystem::path WriteWithFilesBeside(OutputSet& set, const std::filesystem::path& final_path,
                                           const std::function<void(const std::filesystem::path& path)>& write);

// The --json report (cli_report.h) as the set's last output (the injection
// step "report"); nothing when `path` is empty.
void WriteReport(OutputSet& set, const std::string& path, const CommandReport& report);

// "\r<label> [=====     ] done/total" on stderr, a newline when done == total;
// when stderr is not a terminal (a log file), only "<label>: total/total done"
// at the end. Under CommandHooks with a progress callback: that callback instead.
void ProgressBar(const char* label, std::size_t done, std::size_t total);

// A step of a command that draws no bar (total 0: unknown), for
// CommandHooks' progress callback only: nothing on the command line.
void StageProgress(const char* stage, std::size_t done, std::size_t total);

// A library caller's view of a command run in-process on this thread (the
// C ABI's fr_offline_* calls, hosts/c): `progress` gets what ProgressBar and
// StageProgress report and may throw to stop the run (Interrupted: the
// temporaries go, nothing is written); `failed` gets the error Fail reports,
// which then prints nothing. Set while a CommandHooksScope lives.
struct CommandHooks {
  std::function<void(const char* stage, std::size_t done, std::size_t total)> progress;
  std::function<void(const std::exception& error)> failed;
};

class CommandHooksScope {
 public:
  explicit CommandHooksScope(const CommandHooks& hooks);
  ~CommandHooksScope();
  CommandHooksScope(const CommandHooksScope&) = delete;
  CommandHooksScope& operator=(const CommandHooksScope&) = delete;

 private:
  const CommandHooks* previous_;
};

// Prints "facerig: <what>" to stderr and returns exit code 1, or 128 + the
// signal for an Interrupted run (its temporaries gone, nothing written).
int Fail(const std::exception& error);

// Runs a command that writes files and returns its exit code, or Fail's
// when it throws.
int RunWritingCommand(const std::function<int()>& command);

// Fails early (CheckOutputFolder: naming the path as given) when a file
// cannot be created in `path`'s folder, so that a long computation does not
// end in an unwritable path. Missing folders are an error, never created (for
// a folder output, such as --obj-dir, its parent must exist).
void CheckWritable(const std::filesystem::path& path);
// CheckWritable for each output given (empty ones: not asked for).
void CheckWritable(std::initializer_list<std::string> paths);

}  // namespace facerig::cli
