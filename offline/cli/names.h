// --names arkit|ict|keep and --visemes oculus|none, for every `facerig`
// command that writes a rig (standard_shapes.h), and how their result is
// reported: a line on stdout, warnings on stderr, an object in --json.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "cli/options.h"
#include "facerig/offline/rigging/standard_shapes.h"
#include "facerig/runtime/rig_warnings.h"

namespace facerig::cli {

// Adds both options to `app`, filling `options`.
void AddShapeNamingOptions(CLI::App& app, StandardShapesOptions& options);

// The rig as it is written: StandardizeShapes, then the summary printed
// ("shape names arkit: 52 of 52 ARKit names; 15 Oculus visemes baked") and
// each missing ARKit name and warning on stderr. `report` may be null.
Rig NameShapesForWriting(const Rig& rig, const StandardShapesOptions& options,
                         StandardShapesReport* report = nullptr);

// The warnings NameShapesForWriting prints (missing ARKit names, naming
// problems), appended to a report's `warnings`: one list on stderr and in --json.
void AddShapeNamingWarnings(const StandardShapesReport& report, std::vector<RigWarning>& warnings);

// `facerig inspect`: which ARKit names the rig answers and how (exact,
// another spelling, both halves, unsided), the missing ones, its viseme
// targets and the shapes that are neither; printed, and as JSON.
void PrintShapeMatches(const Rig& rig);
nlohmann::json ShapeMatchesJson(const Rig& rig);

// The "names" object of a command's JSON report.
nlohmann::json ShapeNamesJson(const StandardShapesOptions& options, const StandardShapesReport& report);

}  // namespace facerig::cli
