// The steps of `facerig build`, shared by one target (build.cpp) and a cast
// of targets built in one run (build_batch.cpp): the template loaded and
// prepared once (template_preparation.h), then per target its landmarks, the
// build and its outputs with their report.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/common.h"
#include "cli/names.h"
#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/rigging/rig_build.h"
#include "facerig/offline/rigging/template_preparation.h"

namespace facerig::cli {

struct BuildOptions {
  std::string template_path, output, frig, obj_dir, landmarks, report, shape_predictor, template_topology,
      template_info;
  // --target as given (several, or folders of targets, with --output-dir);
  // target_path: the one being built.
  std::vector<std::string> targets;
  std::string target_path;
  std::string output_dir;  // a cast: one output set per target in this folder
  std::string format = "glb";  // a cast's rigs: glb, gltf or frig
  BuildMode mode = BuildMode::kClassic;
  Units units = Units::kUnknown;
  bool contacts = true;  // DeformationTransferParams::contact_weight left at its default, else 0
  bool fit_eyes_to_openings = true;  // LandmarkParams::fit_eyes_to_openings
  StandardShapesOptions naming;
};

// The library's parameters for these options.
BuildRigParams BuildParamsOf(const BuildOptions& options);

// dlib's detector, made when first needed (a target or template without
// landmarks). A cast keeps it for every target; one target lets it go once
// its landmarks are found, so that its model (about 85 MB) is not resident
// while the build peaks.
class SharedLandmarkDetector {
 public:
  SharedLandmarkDetector(const BuildOptions& options, bool keep_for_more_targets);
  LandmarkDetector& Get();
  // After a target's landmarks: frees the detector unless it is kept.
  void LandmarksFound();

 private:
  LandmarkParams params_;
  bool keep_;
  std::optional<LandmarkDetector> detector_;
};

// The template as every target of the run builds from it. Not movable: the
// preparation refers to the rig and the descriptor.
struct BuildTemplate {
  BuildTemplate() = default;
  BuildTemplate(const BuildTemplate&) = delete;
  BuildTemplate& operator=(const BuildTemplate&) = delete;

  Rig rig;
  FaceTemplateInfo info;
  // The descriptor lists the landmark vertices (else they are detected on
  // the template): only then does a target of the template's topology take
  // them as its landmarks instead of detection.
  bool descriptor_has_landmarks = false;
  std::optional<TemplatePreparation> prepared;  // PrepareBuildTemplate
};

// The template rig and its descriptor (--template, --template-info); baked
// visemes dropped when they are made again (--visemes oculus).
std::unique_ptr<BuildTemplate> LoadBuildTemplate(const BuildOptions& options);

// The template's landmark vertices (detected on its renders when its
// descriptor has none) and its preparation (template_preparation.h). A cast
// (for_many_targets) makes the variant most targets use now; one target's
// build makes its own after the registration, so that its peak memory does
// not hold both.
void PrepareBuildTemplate(const BuildOptions& options, BuildTemplate& build_template,
                          SharedLandmarkDetector& detector, bool for_many_targets);

// One target built and written: what the batch summary and the final line say.
struct TargetBuilt {
  std::size_t vertices = 0, shapes = 0;
  double residual_mean_percent = 0.0, residual_p95_percent = 0.0;
};

// Loads options.target_path (its stage "load" into `stages` unless
// `loaded` is given), finds its landmarks, builds it on the prepared template
// and writes options.output and the other outputs asked for, the --json
// report last, as one set; appends each stage's time to `stages`. One
// target (no --output-dir): the template's rig and preparation are freed
// before the writers, so that they do not add to the build's peak memory.
// \throw what loading, detection, the build and the writers throw.
TargetBuilt BuildTargetAndWrite(const BuildOptions& options, BuildTemplate& build_template,
                                SharedLandmarkDetector& detector, std::optional<BuildTarget> loaded,
                                std::vector<BuildStage>& stages);

// Loads the target as `facerig build` reads it (--units applied).
BuildTarget LoadTargetOf(const BuildOptions& options);

}  // namespace facerig::cli
