// `facerig build --output-dir DIR --target T...`: a cast of targets built in
// one run from one template, the template loaded and prepared once
// (template_preparation.h). DIR gets, per target NAME (its file's stem),
// NAME.glb (or --format) and NAME.json, its report, renamed into place last:
// result.status "built", or "failed" with result.error. A failed target is
// reported and skipped; --json writes the cast's summary.
#pragma once

#include "cli/build_steps.h"

namespace facerig::cli {

// The exit code of a cast in which some targets failed (the others built).
inline constexpr int kSomeTargetsFailedExitCode = 3;

// 0 when every target was built, kSomeTargetsFailedExitCode when some
// failed, 1 when the run could not start (the template, DIR) or stopped.
int RunBuildCast(const BuildOptions& options);

}  // namespace facerig::cli
