// Helpers shared by the `facerig` subcommands (tools/cli_*.cpp): adding a
// subcommand, mesh loading for targets, atomic JSON reports, outputs written
// as one set, a progress bar on stderr, timing.
#pragma once

#include <chrono>
#include <cstddef>
#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_options.h"  // SecondsSince
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

// A mesh to work on, as raw data: .obj (positions, UVs, parts, normals kept)
// or any rig format LoadRig reads (.frig, .glb, .gltf, a template folder).
// `units` overrides the file's units when not kUnknown.
RawRig LoadMeshForEditing(const std::filesystem::path& path, Units units = Units::kUnknown);

// Writes `json` (indented) to a temporary file and renames it into place:
// never a partial report. \throw IoError naming the file.
void WriteJsonAtomically(const std::filesystem::path& path, const nlohmann::json& json);

// "\r<label> [=====     ] done/total" on stderr; a newline when done == total.
void ProgressBar(const char* label, std::size_t done, std::size_t total);

// Prints "facerig: <what>" to stderr and returns exit code 1.
int Fail(const std::exception& error);

// Runs a command that writes files and returns its exit code; when it throws,
// 128 + the signal for SIGINT / SIGTERM (saying nothing was written), else
// Fail(error).
int RunWritingCommand(const std::function<int()>& command);

// Writes a command's outputs as one set (output_set.h): `write` adds each
// output to the set and writes its temporary; then all go in place together.
// On any error or SIGINT / SIGTERM the temporaries go and the previous outputs
// stay; an error is rethrown naming the final paths.
void WriteOutputSet(const std::function<void(OutputSet&)>& write);

// Fails early (IoError naming the path) when a file cannot be created in
// `path`'s folder, so a long computation does not end in an unwritable path.
void CheckWritable(const std::filesystem::path& path);

}  // namespace facerig::cli
