#include "cli/commands.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "cli/common.h"
#include "cli/names.h"
#include "cli/obj_folder.h"
#include "cli/options.h"
#include "cli/template_info.h"
#include "facerig/runtime/ascii_case.h"
#include "facerig/offline/render/eye_textures.h"
#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/rigging/rig_build.h"
#include "facerig/runtime/error.h"
#include "facerig/offline/io/build_target.h"
#include "facerig/runtime/io/gltf_with_morph_targets.h"
#include "facerig/runtime/io/gltf.h"
#include "facerig/runtime/io/mtl.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/offline/io/template_folder.h"
#include "facerig/runtime/io/output_set.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/runtime/part_roles.h"
#include "facerig/runtime/rig_surface.h"
#include "facerig/runtime/rig_warnings.h"

namespace facerig::cli {
namespace {

constexpr const char* kBuildDescription =
    "Builds the template's blend shapes on the target mesh's own vertices: landmarks (detected, or\n"
    "--landmarks) -> registration -> transfer (deformation transfer classic / identity-gradient, or\n"
    "displacement matrices) -> mapped onto the target. A glTF target written to .glb/.gltf keeps its\n"
    "skin, nodes, materials, textures and animations: the output is the target's own document with\n"
    "the shapes added as morph targets.";

struct BuildOptions {
  std::string template_path, target_path, output, frig, obj_dir, landmarks, report, shape_predictor,
      template_topology, template_info;
  BuildMode mode = BuildMode::kClassic;
  Units units = Units::kUnknown;
  bool contacts = true;  // DeformationTransferParams::contact_weight left at its default, else 0
  bool fit_eyes_to_openings = true;  // LandmarkParams::fit_eyes_to_openings
  StandardShapesOptions naming;
};

void AddBuildOptions(CLI::App& build, BuildOptions& options) {
  build.add_option("--template", options.template_path, "template: a rig or a folder of OBJs")->required();
  build.add_option("--template-info", options.template_info, "the template's descriptor JSON (default: beside the rig, shipped, or derived)")
      ->check(CLI::ExistingFile);
  build.add_option("--target", options.target_path, "the mesh to rig (OBJ or a rig)")->required();
  build.add_option("-o", options.output, "output rig (.glb, .gltf or .frig)")->required();
  build.add_option("--frig", options.frig, "also write the rig as .frig");
  build.add_option("--obj-dir", options.obj_dir, "also write neutral.obj and one OBJ per shape into DIR");
  AddBuildModeOption(build, options.mode);
  build.add_option("--landmarks", options.landmarks, "the target's landmarks (default: detected)");
  build.add_option("--json", options.report, "write a JSON report");
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
}

bool IsGltf(const std::filesystem::path& path) {
  const std::string extension = LowerExtension(path);
  return extension == ".glb" || extension == ".gltf";
}

// The built rig dressed in the target's surface: its UVs (split at seams)
// and its materials and images, for every output. Parts whose material is a
// placeholder get one of their role (part_roles.h): skin-coloured skin,
// off-white teeth, lashes and eye layers blended, never grey over the eyes;
// eyes without a texture get one painted (iris and pupil in any viewer).
Rig DressedRig(const Rig& rig, Mesh target_mesh) {
  ReplacePlaceholderMaterials(target_mesh);
  PaintEyeTextures(target_mesh);
  std::string problem;
  std::optional<Rig> dressed = RigWithSurface(rig, target_mesh, &problem);
  if (!dressed) throw InvalidInputError("the target's surface does not fit the built rig: " + problem);
  return std::move(*dressed);
}

// A glTF target's own document, with the shapes added, so that a skinned
// character keeps its skin, nodes and materials; else a fresh file of the
// dressed rig.
void SaveBuiltRig(const std::filesystem::path& target, const std::filesystem::path& output, const Rig& rig,
                  const Rig& dressed) {
  if (!IsGltf(target) || !IsGltf(output)) return SaveRig(output, dressed);
  const MorphTargetsWritten written = WriteGltfWithMorphTargets(target, output, rig);
  if (written.replaced_targets > 0) {
    std::fprintf(stderr, "replaced the %zu morph targets mesh '%s' had in %s\n", written.replaced_targets,
                 written.mesh_name.c_str(), target.string().c_str());
  }
}

struct BuildInputs {
  Rig template_rig;
  FaceTemplateInfo template_info;
  BuildTarget target;
  std::size_t target_vertices = 0;
};

BuildInputs LoadBuildInputs(const BuildOptions& options) {
  for (const std::string& path : {options.output, options.frig, options.report, options.template_topology}) {
    if (!path.empty()) CheckWritable(path);
  }
  if (!options.obj_dir.empty()) CheckWritable(options.obj_dir);
  BuildInputs inputs;
  inputs.template_rig = LoadRigOrTemplateFolder(options.template_path);
  // Baked visemes are made again from the built shapes: no need to transfer them.
  if (options.naming.visemes == VisemeTargets::kOculus) inputs.template_rig = WithoutBakedVisemes(inputs.template_rig);
  inputs.template_info = ResolveFaceTemplateInfo(inputs.template_rig, options.template_path, options.template_info);
  inputs.target = LoadBuildTarget(options.target_path, options.units);
  inputs.target_vertices = inputs.target.rig.positions.size();
  return inputs;
}

struct BuildLandmarks {
  RegistrationLandmarks pairs;
  std::string source;          // the --landmarks file, "detected" or "template topology"
  int target_eyes_fitted = 0;  // detected eyes put on the target's eye openings
};

// The target's landmarks (read or detected) paired with the template's (found
// on the template when its descriptor has none: inputs.template_info gets them).
BuildLandmarks FindBuildLandmarks(const BuildOptions& options, BuildInputs& inputs) {
  LandmarkParams landmark_params;
  if (!options.shape_predictor.empty()) landmark_params.shape_predictor = options.shape_predictor;
  landmark_params.fit_eyes_to_openings = options.fit_eyes_to_openings;
  std::optional<LandmarkDetector> detector;
  auto get_detector = [&]() -> LandmarkDetector& {
    if (!detector) detector.emplace(landmark_params);
    return *detector;
  };
  BuildLandmarks found;
  FaceLandmarks target_landmarks;
  const std::optional<FaceLandmarks> on_template_topology = LandmarksOnTemplateTopology(
      inputs.template_rig, inputs.template_info, inputs.target.rig.positions, inputs.target.rig.triangles);
  if (!options.landmarks.empty()) {
    target_landmarks = ReadLandmarksJson(options.landmarks);
    found.source = options.landmarks;
  } else if (on_template_topology) {
    std::fputs("the target has the template's topology: its landmarks are the template's landmark vertices\n", stderr);
    target_landmarks = *on_template_topology;
    found.source = "template topology";
  } else {
    found.source = "detected";
    std::fputs("detecting landmarks on the target...\n", stderr);
    LandmarkResult detected = get_detector().Detect(NeutralMesh(inputs.target.rig));
    target_landmarks = std::move(detected.landmarks);
    found.target_eyes_fitted = detected.eyes_fitted;
  }
  const std::vector<std::uint32_t> template_vertex_of =
      TemplateLandmarkVertices(inputs.template_rig, inputs.template_info, get_detector());
  PrintTemplateInfo(inputs.template_info);
  found.pairs = PairLandmarks(template_vertex_of, target_landmarks);
  return found;
}

// Where the outputs without files beside them go until OutputSet::Commit()
// (empty: not asked for). The rig and --template-topology may bring an OBJ's
// MTL and images: WriteWithFilesBeside adds them as they are written.
struct BuildOutputPaths {
  std::filesystem::path frig, obj_dir, report;
};

// The outputs as one set (output_set.h): --obj-dir is replaced, not merged,
// and only when it holds nothing but what WriteRigObjFolder writes.
BuildOutputPaths AddBuildOutputs(const BuildOptions& options, OutputSet& set) {
  const auto add_file = [&set](const std::string& path) {
    return path.empty() ? std::filesystem::path() : set.Add(path, OutputSet::Kind::kFile);
  };
  BuildOutputPaths paths;
  paths.frig = add_file(options.frig);
  if (!options.obj_dir.empty()) paths.obj_dir = AddObjFolderOutput(set, options.obj_dir);
  paths.report = add_file(options.report);
  return paths;
}

// Writes every output but the report under its temporary name.
void WriteBuildOutputs(const BuildOptions& options, const BuildOutputPaths& paths, const Rig& rig,
                       const BuildRigResult& built, OutputSet& set) {
  const Rig dressed = DressedRig(rig, built.target_mesh);
  const std::filesystem::path rig_path = WriteWithFilesBeside(
      set, options.output, [&](const std::filesystem::path& path) { SaveBuiltRig(options.target_path, path, rig, dressed); });
  CheckAfterWrite("rig", rig_path);
  if (!paths.frig.empty()) {
    SaveRig(paths.frig, dressed);
    CheckAfterWrite("frig", paths.frig);
  }
  if (!paths.obj_dir.empty()) {
    WriteRigObjFolder(paths.obj_dir, dressed);
    CheckAfterWrite("obj-dir", paths.obj_dir);
  }
  if (!options.template_topology.empty()) {
    std::string problem;
    const std::optional<Rig> fitted = RigBuilder::Build(built.template_frame_rig, &problem);
    if (!fitted) throw InvalidInputError("the template-topology rig is invalid: " + problem);
    const Rig named = StandardizeShapes(*fitted, options.naming).rig;
    const std::filesystem::path fitted_path = WriteWithFilesBeside(
        set, options.template_topology, [&](const std::filesystem::path& path) { SaveRig(path, named); });
    CheckAfterWrite("template-topology", fitted_path);
  }
}

nlohmann::json RegistrationReport(const BuildRigResult& built) {
  const ResidualStats& residual = built.registration.residual;
  return {{"residual_percent_of_diagonal",
           {{"mean", residual.mean_percent}, {"p95", residual.p95_percent}, {"max", residual.max_percent}}},
          {"landmark_rms", built.registration.landmark_rms},
          {"rigid_scale", built.registration.rigid.scale},
          {"iterations_per_stage", built.registration.iterations_per_stage}};
}

nlohmann::json MappingReport(const TopologyMapping& mapping) {
  return {{"full_weight_vertices", mapping.full_vertices},
          {"rim_vertices", mapping.rim_vertices},
          {"partial_weight_vertices", mapping.partial_vertices},
          {"unmapped_vertices", mapping.unmapped_vertices},
          {"facing_fallbacks", mapping.facing_fallbacks},
          {"mean_distance", mapping.mean_distance}};
}

// Every stage of the command in order, with its time: the CLI's own (load,
// landmarks, write) around the library's (BuildRigResult::stages).
nlohmann::json StagesReport(std::span<const BuildStage> stages) {
  nlohmann::json list = nlohmann::json::array();
  for (const BuildStage& stage : stages) list.push_back({{"name", stage.name}, {"seconds", stage.seconds}});
  return list;
}

CommandReport BuildReport(const BuildOptions& options, const BuildInputs& inputs, const BuildLandmarks& landmarks,
                          const BuildRigResult& built, const Rig& rig, const StandardShapesReport& names,
                          std::span<const BuildStage> stages) {
  CommandReport envelope{"build",
                         {{"template", options.template_path},
                          {"template_info", options.template_info},
                          {"target", options.target_path},
                          {"landmarks", options.landmarks},
                          {"shape_predictor", options.shape_predictor}},
                         {{"rig", options.output},
                          {"frig", options.frig},
                          {"obj_dir", options.obj_dir},
                          {"template_topology", options.template_topology}},
                         // A rig that cannot speak or blink (its template had no such shapes) says so here.
                         SpeechAndBlinkWarnings(rig)};
  AddShapeNamingWarnings(names, envelope.warnings);
  nlohmann::json& report = envelope.result;
  report["shape_names"] = ShapeNamesJson(options.naming, names);
  report["mode"] = ToString(options.mode);
  report["template_info"] = TemplateInfoReport(inputs.template_info);
  report["target_vertices"] = inputs.target_vertices;
  report["shapes"] = rig.shape_count();
  report["shape_names"] = ShapeNamesJson(options.naming, names);
  report["units"] = ToString(rig.units());
  report["landmarks"] = landmarks.source;
  report["options"] = {{"contacts", options.contacts}, {"eye_fit", options.fit_eyes_to_openings}};
  report["target_eyes_fitted"] = landmarks.target_eyes_fitted;
  report["registration"] = RegistrationReport(built);
  report["transfer_anchors"] = built.transfer_anchors;
  // The template had no tongueOut: made from this part of it (null: it had one, or no tongue).
  report["tongue_out_synthesised_from"] = built.tongue_out_synthesised_from.empty()
                                              ? nlohmann::json(nullptr)
                                              : nlohmann::json(built.tongue_out_synthesised_from);
  report["transfer_contacts"] = {{"active", built.transfer_contacts_active}, {"pairs", built.transfer_contacts}};
  // Template lid margins moved onto the target's eye rims before the transfer.
  report["margin_alignment"] = {{"vertices", built.margin_vertices_aligned},
                                {"mean_move", built.margin_mean_correction}};
  report["mapping"] = MappingReport(built.mapping);
  report["stages"] = StagesReport(stages);
  envelope.timings = {{"load", StageSeconds(stages, "load")},
                      {"landmarks", StageSeconds(stages, "landmarks")},
                      {"register", built.timings.registration_seconds},
                      {"transfer", built.timings.transfer_seconds},
                      {"map", built.timings.mapping_seconds},
                      {"write", StageSeconds(stages, "write")},
                      {"total", TotalSeconds(stages)}};
  return envelope;
}

// Writes the outputs under temporary names (the "write" stage, then the report)
// and puts them in place as one set; on any error or SIGINT / SIGTERM the
// temporaries go and the previous set stays.
void WriteBuildSet(const BuildOptions& options, const BuildInputs& inputs, const BuildLandmarks& landmarks,
                   const BuildRigResult& built, const Rig& rig, const StandardShapesReport& names,
                   std::vector<BuildStage>& stages) {
  WriteOutputSet([&](OutputSet& set) {
    const BuildOutputPaths paths = AddBuildOutputs(options, set);
    TimeStage(stages, "write", [&] { WriteBuildOutputs(options, paths, rig, built, set); });
    if (!paths.report.empty()) {
      WriteCommandReport(paths.report, BuildReport(options, inputs, landmarks, built, rig, names, stages));
      CheckAfterWrite("report", paths.report);
    }
  });
}

int BuildAndWrite(const BuildOptions& options) {
  std::vector<BuildStage> stages;
  BuildInputs inputs = TimeStage(stages, "load", [&] { return LoadBuildInputs(options); });
  std::fprintf(stderr, "template %zu vertices, %zu shapes; target %zu vertices (%.2f s to load)\n",
               inputs.template_rig.vertex_count(), inputs.template_rig.shape_count(), inputs.target_vertices,
               stages.back().seconds);
  const BuildLandmarks landmarks = TimeStage(stages, "landmarks", [&] { return FindBuildLandmarks(options, inputs); });

  BuildRigParams params;
  params.mode = options.mode;
  if (!options.contacts) params.transfer.contact_weight = 0.0;
  params.progress = [](const char* stage, std::size_t done, std::size_t total) { ProgressBar(stage, done, total); };
  const BuildRigResult built =
      BuildRig(inputs.template_rig, inputs.template_info, std::move(inputs.target), landmarks.pairs, params);
  stages.insert(stages.end(), built.stages.begin(), built.stages.end());
  if (!built.tongue_out_synthesised_from.empty()) {
    std::fprintf(stderr, "the template has no tongueOut: made one from its part '%s'\n",
                 built.tongue_out_synthesised_from.c_str());
  }
  std::string problem;
  const std::optional<Rig> unnamed = RigBuilder::Build(built.rig, &problem);
  if (!unnamed) throw InvalidInputError("the built rig is invalid: " + problem);
  StandardShapesReport names;
  const std::optional<Rig> rig = NameShapesForWriting(*unnamed, options.naming, &names);
  WriteBuildSet(options, inputs, landmarks, built, *rig, names, stages);

  const ResidualStats& residual = built.registration.residual;
  std::printf("wrote %s: %zu vertices (the target's), %zu shapes, mode %s, units %s; registration residual mean "
              "%.4f%% p95 %.4f%% of the diagonal; %.2f s\n",
              options.output.c_str(), rig->vertex_count(), rig->shape_count(), ToString(options.mode),
              ToString(rig->units()), residual.mean_percent, residual.p95_percent,
              TotalSeconds(stages));
  return 0;
}

int RunBuild(const BuildOptions& options) {
  return RunWritingCommand([&options] { return BuildAndWrite(options); });
}

}  // namespace

void AddBuildCommand(CLI::App& facerig, CommandBody& body) {
  const auto [build, options] =
      AddSubcommand(facerig, body, "build", "a rig for a new face, end to end", kBuildDescription, RunBuild);
  AddBuildOptions(*build, *options);
}

}  // namespace facerig::cli
