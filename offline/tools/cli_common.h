// Helpers shared by the `facerig` subcommands (tools/cli_*.cpp): mesh loading
// for targets, atomic JSON reports, a progress bar on stderr, timing.
#pragma once

#include <chrono>
#include <cstddef>
#include <exception>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_options.h"  // SecondsSince
#include "facerig/runtime/rig_builder.h"

namespace facerig::cli {

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

// Fails early (IoError naming the path) when a file cannot be created in
// `path`'s folder, so a long computation does not end in an unwritable path.
void CheckWritable(const std::filesystem::path& path);

}  // namespace facerig::cli
