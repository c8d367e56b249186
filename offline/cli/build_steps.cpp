#include "cli/build_steps.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "cli/obj_folder.h"
#include "cli/template_info.h"
#include "facerig/offline/io/build_target.h"
#include "facerig/offline/io/template_folder.h"
#include "facerig/offline/render/eye_textures.h"
#include "facerig/offline/rigging/lid_choice.h"
#include "facerig/runtime/ascii_case.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/io/gltf_with_morph_targets.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/runtime/part_roles.h"
#include "facerig/runtime/rig_surface.h"
#include "facerig/runtime/rig_warnings.h"

namespace facerig::cli {
namespace {

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

struct BuildLandmarks {
  FaceLandmarks target;             // the target's own (paired by BuildRigChoosingLids)
  DoubtfulLidPoints doubtful_lids;  // detected: LandmarkResult's
  std::string source;          // the --landmarks file, "detected" or "template topology"
  int target_eyes_fitted = 0;  // detected eyes put on the target's eye openings
};

// The target's landmarks: read, on the template's topology, or detected.
BuildLandmarks FindBuildLandmarks(const BuildOptions& options, const BuildTemplate& build_template,
                                  const RawRig& target, SharedLandmarkDetector& detector) {
  BuildLandmarks found;
  FaceLandmarks target_landmarks;
  const std::optional<FaceLandmarks> on_template_topology =
      build_template.descriptor_has_landmarks
          ? LandmarksOnTemplateTopology(build_template.rig, build_template.info, target.positions, target.triangles)
          : std::nullopt;
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
    LandmarkResult detected = detector.Get().Detect(NeutralMesh(target));
    target_landmarks = std::move(detected.landmarks);
    found.target_eyes_fitted = detected.eyes_fitted;
    found.doubtful_lids = std::move(detected.doubtful_lids);
  }
  found.target = std::move(target_landmarks);
  return found;
}

// Where the outputs without files beside them go until OutputSet::Commit()
// (empty: not asked for). The rig and --template-topology may bring an OBJ's
// MTL and images: WriteWithFilesBeside adds them as they are written.
struct BuildOutputPaths {
  std::filesystem::path frig, obj_dir;
};

// The outputs as one set (output_set.h): --obj-dir is replaced, not merged,
// and only when it holds nothing but what WriteRigObjFolder writes.
BuildOutputPaths AddBuildOutputs(const BuildOptions& options, OutputSet& set) {
  BuildOutputPaths paths;
  paths.frig = AddOptionalFile(set, options.frig);
  if (!options.obj_dir.empty()) paths.obj_dir = AddObjFolderOutput(set, options.obj_dir);
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

// What the report says of the target and its build, besides the rig.
struct BuildFacts {
  const FaceTemplateInfo& template_info;
  std::size_t target_vertices = 0;
  const BuildLandmarks& landmarks;
  const BuildRigResult& built;
  const LidChoice& lids;
};

// Doubtful lid landmarks: which, and which of the two builds was kept (null: no second build).
nlohmann::json LidChoiceReport(const DoubtfulLidPoints& doubtful, const LidChoice& lids) {
  const nlohmann::json points = IndicesOf(doubtful.points);
  if (!lids.tried) return {{"points", points}, {"kept", nullptr}};
  return {{"points", points},
          {"kept", lids.trusted ? "trusted" : "dropped"},
          {"blink_stretch_trusted", lids.trusted_stretch},
          {"blink_stretch_dropped", lids.dropped_stretch}};
}

CommandReport BuildReport(const BuildOptions& options, const BuildFacts& facts, const Rig& rig,
                          const StandardShapesReport& names, std::span<const BuildStage> stages) {
  const BuildRigResult& built = facts.built;
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
  report["template_info"] = TemplateInfoReport(facts.template_info);
  report["target_vertices"] = facts.target_vertices;
  report["shapes"] = rig.shape_count();
  report["units"] = ToString(rig.units());
  report["landmarks"] = facts.landmarks.source;
  report["options"] = {{"contacts", options.contacts}, {"eye_fit", options.fit_eyes_to_openings}};
  report["target_eyes_fitted"] = facts.landmarks.target_eyes_fitted;
  report["doubtful_lid_landmarks"] = LidChoiceReport(facts.landmarks.doubtful_lids, facts.lids);
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
  // A cast's report says it was built: what a resumed run looks for.
  if (!options.output_dir.empty()) report["status"] = "built";
  envelope.timings = {{"load", StageSeconds(stages, "load")},
                      {"prepare_template", StageSeconds(stages, "prepare template")},
                      {"landmarks", StageSeconds(stages, "landmarks")},
                      {"register", built.timings.registration_seconds},
                      {"transfer", built.timings.transfer_seconds},
                      {"map", built.timings.mapping_seconds},
                      {"lid_choice", StageSeconds(stages, "lid choice")},
                      {"write", StageSeconds(stages, "write")},
                      {"total", TotalSeconds(stages)}};
  return envelope;
}

// Writes the outputs under temporary names (the "write" stage, then the
// report, added last so that it is renamed into place last) and puts them in
// place as one set; on any error or SIGINT / SIGTERM the temporaries go and
// the previous set stays.
void WriteBuildSet(const BuildOptions& options, const BuildFacts& facts, const Rig& rig,
                   const StandardShapesReport& names, std::vector<BuildStage>& stages) {
  WriteOutputSet([&](OutputSet& set) {
    const BuildOutputPaths paths = AddBuildOutputs(options, set);
    TimeStage(stages, "write", [&] { WriteBuildOutputs(options, paths, rig, facts.built, set); });
    WriteReport(set, options.report, BuildReport(options, facts, rig, names, stages));
  });
}

}  // namespace

BuildRigParams BuildParamsOf(const BuildOptions& options) {
  BuildRigParams params;
  params.mode = options.mode;
  if (!options.contacts) params.transfer.contact_weight = 0.0;
  params.progress = [](const char* stage, std::size_t done, std::size_t total) { ProgressBar(stage, done, total); };
  return params;
}

SharedLandmarkDetector::SharedLandmarkDetector(const BuildOptions& options, bool keep_for_more_targets)
    : keep_(keep_for_more_targets) {
  if (!options.shape_predictor.empty()) params_.shape_predictor = options.shape_predictor;
  params_.fit_eyes_to_openings = options.fit_eyes_to_openings;
}

LandmarkDetector& SharedLandmarkDetector::Get() {
  if (!detector_) detector_.emplace(params_);
  return *detector_;
}

void SharedLandmarkDetector::LandmarksFound() {
  if (!keep_) detector_.reset();
}

std::unique_ptr<BuildTemplate> LoadBuildTemplate(const BuildOptions& options) {
  auto loaded = std::make_unique<BuildTemplate>();
  loaded->rig = LoadTemplateRig(options.template_path);
  // Baked visemes are made again from the built shapes: no need to transfer them.
  if (options.naming.visemes == VisemeTargets::kOculus) loaded->rig = WithoutBakedVisemes(loaded->rig);
  loaded->info = ResolveFaceTemplateInfo(loaded->rig, options.template_path, options.template_info);
  loaded->descriptor_has_landmarks = !loaded->info.landmark_vertices.empty();
  return loaded;
}

void PrepareBuildTemplate(const BuildOptions& options, BuildTemplate& build_template,
                          SharedLandmarkDetector& detector, bool for_many_targets) {
  if (build_template.info.landmark_vertices.empty()) {
    TemplateLandmarkVertices(build_template.rig, build_template.info, detector.Get());
  }
  PrintTemplateInfo(build_template.info);
  build_template.prepared.emplace(build_template.rig, build_template.info, BuildParamsOf(options));
  if (!for_many_targets) return;
  const PreparedTemplate& variant = build_template.prepared->For(false);
  if (!variant.tongue_out_synthesised_from.empty()) {
    std::fprintf(stderr, "the template has no tongueOut: made one from its part '%s'\n",
                 variant.tongue_out_synthesised_from.c_str());
  }
}

BuildTarget LoadTargetOf(const BuildOptions& options) { return LoadBuildTarget(options.target_path, options.units); }

TargetBuilt BuildTargetAndWrite(const BuildOptions& options, BuildTemplate& build_template,
                                SharedLandmarkDetector& detector, std::optional<BuildTarget> loaded,
                                std::vector<BuildStage>& stages) {
  BuildTarget target = loaded ? std::move(*loaded) : TimeStage(stages, "load", [&] { return LoadTargetOf(options); });
  const std::size_t target_vertices = target.rig.positions.size();
  if (!loaded) std::fprintf(stderr, "target %zu vertices (%.2f s to load)\n", target_vertices, stages.back().seconds);
  const BuildLandmarks landmarks = TimeStage(
      stages, "landmarks", [&] { return FindBuildLandmarks(options, build_template, target.rig, detector); });
  detector.LandmarksFound();

  LidChoice lids;
  const auto build_start = std::chrono::steady_clock::now();
  const BuildRigResult built = BuildRigChoosingLids(*build_template.prepared, target,
                                                    build_template.info.landmark_vertices, landmarks.target,
                                                    landmarks.doubtful_lids, BuildParamsOf(options), &lids);
  stages.insert(stages.end(), built.stages.begin(), built.stages.end());
  if (lids.tried) {  // the other build ran beside this one: the time spent waiting for it
    stages.push_back({"lid choice", std::max(0.0, SecondsSince(build_start) - built.timings.total_seconds)});
    std::fprintf(stderr, "%zu lid landmarks lay on the eye, not the skin: built with them and without, kept the "
                 "build %s them (its blinks stretch an edge %.2fx, the other %.2fx)\n",
                 landmarks.doubtful_lids.points.count(), lids.trusted ? "with" : "without",
                 lids.trusted ? lids.trusted_stretch : lids.dropped_stretch,
                 lids.trusted ? lids.dropped_stretch : lids.trusted_stretch);
  }
  if (options.output_dir.empty() && !built.tongue_out_synthesised_from.empty()) {  // a cast said it once
    std::fprintf(stderr, "the template has no tongueOut: made one from its part '%s'\n",
                 built.tongue_out_synthesised_from.c_str());
  }
  if (options.output_dir.empty()) {
    build_template.prepared.reset();
    build_template.rig = Rig();
  }
  std::string problem;
  const std::optional<Rig> unnamed = RigBuilder::Build(built.rig, &problem);
  if (!unnamed) throw InvalidInputError("the built rig is invalid: " + problem);
  StandardShapesReport names;
  const std::optional<Rig> rig = NameShapesForWriting(*unnamed, options.naming, &names);
  WriteBuildSet(options, {build_template.info, target_vertices, landmarks, built, lids}, *rig, names, stages);

  const ResidualStats& residual = built.registration.residual;
  std::printf("wrote %s: %zu vertices (the target's), %zu shapes, mode %s, units %s; registration residual mean "
              "%.4f%% p95 %.4f%% of the diagonal; %.2f s\n",
              options.output.c_str(), rig->vertex_count(), rig->shape_count(), ToString(options.mode),
              ToString(rig->units()), residual.mean_percent, residual.p95_percent, TotalSeconds(stages));
  return {rig->vertex_count(), rig->shape_count(), residual.mean_percent, residual.p95_percent};
}

}  // namespace facerig::cli
