#include "cli/commands.h"

#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli/build_batch.h"
#include "cli/build_steps.h"
#include "cli/common.h"
#include "cli/names.h"
#include "cli/options.h"

namespace facerig::cli {
namespace {

constexpr const char* kBuildDescription =
    "Builds the template's blend shapes on the target mesh's own vertices: landmarks (detected, or\n"
    "--landmarks) -> registration -> transfer (deformation transfer classic / identity-gradient, or\n"
    "displacement matrices) -> mapped onto the target. A glTF target written to .glb/.gltf keeps its\n"
    "skin, nodes, materials, textures and animations: the output is the target's own document with\n"
    "the shapes added as morph targets.\n"
    "A cast: with --output-dir, every --target (several, or folders of targets) is built in one run,\n"
    "the template's own work done once; DIR gets NAME.glb and NAME.json (its report) per target. A\n"
    "target that fails is reported (its error in its report and the summary) and skipped; the exit\n"
    "code is then 3.";

// The options a cast (--output-dir) cannot take: each names one target's file.
constexpr const char* kSingleTargetOptions[] = {"-o", "--frig", "--obj-dir", "--landmarks", "--template-topology"};

void AddBuildOptions(CLI::App& build, BuildOptions& options) {
  build.add_option("--template", options.template_path, "template: a rig or a folder of OBJs")->required();
  build.add_option("--template-info", options.template_info, "the template's descriptor JSON (default: beside the rig, shipped, or derived)")
      ->check(CLI::ExistingFile);
  build.add_option("--target", options.targets,
                   "the mesh to rig (OBJ or a rig); with --output-dir, several, or folders of them")
      ->required();
  build.add_option("-o", options.output, "output rig (.glb, .gltf or .frig)");
  build.add_option("--output-dir", options.output_dir,
                   "build every --target in one run: DIR/NAME.glb and DIR/NAME.json per target");
  build.add_option("--format", options.format, "with --output-dir: the rigs' format (default glb)")
      ->check(CLI::IsMember({"glb", "gltf", "frig"}));
  build.add_option("--frig", options.frig, "also write the rig as .frig");
  build.add_option("--obj-dir", options.obj_dir, "also write neutral.obj and one OBJ per shape into DIR");
  AddBuildModeOption(build, options.mode);
  build.add_option("--landmarks", options.landmarks, "the target's landmarks (default: detected)");
  build.add_option("--json", options.report, "write a JSON report (with --output-dir: the cast's summary)");
  AddUnitsOption(build, options.units,
                 "the target's units when its file does not say (default: inferred from the registration's scale)");
  build.add_option("--template-topology", options.template_topology,
                   "also write the rig on the template's vertices, frame and units (for average, caricature, morph)");
  build.add_option("--shape-predictor", options.shape_predictor, "dlib 68-point shape predictor file");
  AddOffFlag(build, "--no-contacts", options.contacts,
                 "transfer without contacts (where a template expression closes an opening, the target's closes too)");
  AddOffFlag(build, "--no-eye-fit", options.fit_eyes_to_openings,
                 "keep the detector's eye landmarks instead of fitting them to the mesh's eye openings");
  AddShapeNamingOptions(build, options.naming);
  // One target with -o, or a cast with --output-dir: a bad mix is a bad command line (exit 2).
  build.parse_complete_callback([&build, &options] {
    if (options.output_dir.empty()) {
      if (options.output.empty()) throw CLI::RequiredError("-o (or --output-dir for a cast)");
      if (options.targets.size() != 1) {
        throw CLI::ValidationError("--target", "one target with -o; several need --output-dir");
      }
      if (build.count("--format") > 0) throw CLI::ValidationError("--format", "goes with --output-dir");
      return;
    }
    for (const char* name : kSingleTargetOptions) {
      if (build.count(name) > 0) throw CLI::ValidationError(name, "names one target's file: not with --output-dir");
    }
  });
}

int BuildAndWrite(BuildOptions options) {
  options.target_path = options.targets.front();
  CheckWritable({options.output, options.frig, options.report, options.template_topology});
  if (!options.obj_dir.empty()) CheckWritable(options.obj_dir);
  std::vector<BuildStage> stages;
  std::unique_ptr<BuildTemplate> build_template;
  std::optional<BuildTarget> target = TimeStage(stages, "load", [&] {
    build_template = LoadBuildTemplate(options);
    return std::optional<BuildTarget>(LoadTargetOf(options));
  });
  std::fprintf(stderr, "template %zu vertices, %zu shapes; target %zu vertices (%.2f s to load)\n",
               build_template->rig.vertex_count(), build_template->rig.shape_count(), target->rig.positions.size(),
               stages.back().seconds);
  SharedLandmarkDetector detector(options, false);
  TimeStage(stages, "prepare template", [&] { PrepareBuildTemplate(options, *build_template, detector, false); });
  BuildTargetAndWrite(options, *build_template, detector, std::move(target), stages);
  return 0;
}

int RunBuild(const BuildOptions& options) {
  if (!options.output_dir.empty()) return RunBuildCast(options);
  return RunWritingCommand([&options] { return BuildAndWrite(options); });
}

}  // namespace

void AddBuildCommand(CLI::App& facerig, CommandBody& body) {
  const auto [build, options] =
      AddSubcommand(facerig, body, "build", "a rig for a new face, end to end", kBuildDescription, RunBuild);
  AddBuildOptions(*build, *options);
}

}  // namespace facerig::cli
