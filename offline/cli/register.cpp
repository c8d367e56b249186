#include "cli/commands.h"

#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "cli/common.h"
#include "cli/options.h"
#include "cli/template_info.h"
#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/registration/nonrigid_icp.h"
#include "facerig/offline/render/rasterizer.h"
#include "facerig/offline/error.h"
#include "facerig/offline/rigging/rig_build.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/offline/io/template_folder.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig::cli {
namespace {

struct LandmarksOptions {
  std::string mesh_path, output, debug_png, report_path;
  LandmarkParams params;
};

struct RegisterOptions {
  std::string template_path, target_path, output, landmarks_path, report_path;
  LandmarkParams landmark_params;
  std::string template_info_path;
};

CommandReport LandmarksReport(const LandmarksOptions& options, const RawRig& mesh, const LandmarkResult& result,
                              double load_seconds, double model_seconds) {
  CommandReport report{"landmarks",
                       {{"mesh", options.mesh_path}, {"shape_predictor", options.params.shape_predictor.string()}},
                       {{"landmarks", options.output}, {"debug_png", options.debug_png}}};
  report.timings = {{"load_mesh", load_seconds},
                    {"load_model", model_seconds},
                    {"detect", result.seconds},
                    {"total", load_seconds + model_seconds + result.seconds}};
  report.result = {{"vertices", mesh.positions.size()},
                   {"views_tried", result.views_tried},
                   {"eyes_fitted_to_openings", result.eyes_fitted},
                   // Lid points on the eye, not the skin: confidence 0 in the landmarks file.
                   {"doubtful_lid_points", IndicesOf(result.doubtful_lids.points)},
                   {"snapped", result.snapped},
                   {"detector_score", result.detector_score}};
  return report;
}

// The landmarks JSON, the debug PNG (under a temporary name that keeps its
// extension, which picks the image format) and the report, as one set.
void WriteLandmarksSet(const LandmarksOptions& options, const LandmarkResult& result, const CommandReport& report) {
  WriteOutputSet([&](OutputSet& set) {
    const std::filesystem::path landmarks = set.Add(options.output, OutputSet::Kind::kFile);
    WriteLandmarksJson(landmarks, result.landmarks);
    CheckAfterWrite("landmarks", landmarks);
    if (const std::filesystem::path png = AddOptionalFile(set, options.debug_png); !png.empty()) {
      WritePng(png, DrawLandmarks(result));
      CheckAfterWrite("debug-png", png);
    }
    WriteReport(set, options.report_path, report);
  });
}

int RunLandmarks(const LandmarksOptions& options) {
  try {
    CheckWritable({options.output, options.debug_png, options.report_path});
    const auto start = std::chrono::steady_clock::now();
    const RawRig mesh = LoadMeshForEditing(options.mesh_path);
    const double load_seconds = SecondsSince(start);
    std::fprintf(stderr, "%s: %zu vertices, %zu triangles (%.2f s to load); detecting landmarks...\n",
                 options.mesh_path.c_str(), mesh.positions.size(), mesh.triangles.size(), load_seconds);
    const auto model_start = std::chrono::steady_clock::now();
    LandmarkDetector detector(options.params);
    const double model_seconds = SecondsSince(model_start);
    const LandmarkResult result = detector.Detect(NeutralMesh(mesh));
    WriteLandmarksSet(options, result, LandmarksReport(options, mesh, result, load_seconds, model_seconds));
    std::printf(
        "wrote %s (68 landmarks; %d views tried, %d snapped off holes, %d eyes fitted to openings, detector score "
        "%.2f; %.3f s)\n",
        options.output.c_str(), result.views_tried, result.snapped, result.eyes_fitted, result.detector_score,
        result.seconds);
    return 0;
  } catch (const std::exception& error) {
    return Fail(error);
  }
}

// The target's landmarks (from --landmarks or detected) paired with the
// template's landmark vertices; the detector is loaded only when needed.
RegistrationLandmarks FindRegisterLandmarks(const RegisterOptions& options, const Rig& rig, const RawRig& target,
                                            FaceTemplateInfo& template_info) {
  std::optional<LandmarkDetector> detector;
  auto get_detector = [&]() -> LandmarkDetector& {
    if (!detector) detector.emplace(options.landmark_params);
    return *detector;
  };
  FaceLandmarks target_landmarks;
  if (!options.landmarks_path.empty()) {
    target_landmarks = ReadLandmarksJson(options.landmarks_path);
  } else {
    std::fprintf(stderr, "detecting landmarks on the target...\n");
    target_landmarks = get_detector().Detect(NeutralMesh(target)).landmarks;
  }
  if (template_info.landmark_vertices.empty()) std::fprintf(stderr, "detecting landmarks on the template...\n");
  const std::vector<std::uint32_t> template_vertex_of = TemplateLandmarkVertices(rig, template_info, get_detector());
  PrintTemplateInfo(template_info);
  return PairLandmarks(template_vertex_of, target_landmarks);
}

CommandReport RegisterReport(const RegisterOptions& options, const FaceTemplateInfo& template_info,
                             const NonrigidIcpResult& fit) {
  const ResidualStats& residual = fit.residual;
  CommandReport report{"register",
                       {{"template", options.template_path},
                        {"template_info", options.template_info_path},
                        {"target", options.target_path},
                        {"landmarks", options.landmarks_path}},
                       {{"fitted", options.output}}};
  report.result = {{"landmarks", options.landmarks_path.empty() ? "detected" : options.landmarks_path},
                   {"template_info", TemplateInfoReport(template_info)},
                   {"residual_percent_of_diagonal",
                    {{"mean", residual.mean_percent}, {"p95", residual.p95_percent}, {"max", residual.max_percent}}},
                   {"target_diagonal", residual.target_diagonal},
                   {"measured_vertices", residual.vertex_count},
                   {"rejected_vertices", residual.rejected_count},
                   {"landmark_rms", fit.landmark_rms},
                   {"rigid_scale", fit.rigid.scale},
                   {"iterations_per_stage", fit.iterations_per_stage},
                   {"factorizations", fit.factorizations}};
  return report;
}

// The fitted OBJ and the report, as one set.
void WriteRegisterSet(const RegisterOptions& options, const Rig& rig, const NonrigidIcpResult& fit,
                      const CommandReport& report) {
  std::vector<glm::vec3> normals(fit.positions.size());
  ComputeVertexNormals(fit.positions, rig.triangles(), normals);
  WriteOutputSet([&](OutputSet& set) {
    const std::filesystem::path obj = set.Add(options.output, OutputSet::Kind::kFile);
    WriteObj(obj, fit.positions, normals, rig.uvs(), rig.triangles(), rig.parts());
    CheckAfterWrite("obj", obj);
    WriteReport(set, options.report_path, report);
  });
}

int RunRegister(const RegisterOptions& options) {
  try {
    CheckWritable({options.output, options.report_path});
    const auto start = std::chrono::steady_clock::now();
    const Rig rig = LoadTemplateRig(options.template_path);
    const RawRig target = LoadMeshForEditing(options.target_path);
    const double load_seconds = SecondsSince(start);
    std::fprintf(stderr, "template %zu vertices, target %zu vertices (%.2f s to load)\n", rig.vertex_count(),
                 target.positions.size(), load_seconds);

    const auto landmark_start = std::chrono::steady_clock::now();
    FaceTemplateInfo template_info =
        ResolveFaceTemplateInfo(rig, options.template_path, options.template_info_path);
    const RegistrationLandmarks landmarks = FindRegisterLandmarks(options, rig, target, template_info);
    const double landmark_seconds = SecondsSince(landmark_start);

    NonrigidIcpParams params;
    params.region_vertex_count = template_info.region.last + 1;
    std::fprintf(stderr, "rigid alignment and non-rigid ICP (%zu landmarks)...\n", landmarks.target_points.size());
    params.progress = [](std::size_t done, std::size_t total) { ProgressBar("non-rigid ICP", done, total); };
    const NonrigidIcpResult fit = NonrigidIcp(NeutralMesh(rig), NeutralMesh(target), landmarks, params);

    CommandReport report = RegisterReport(options, template_info, fit);
    const NonrigidIcpTimings& timings = fit.timings;
    report.timings = {{"load", load_seconds},
                         {"landmarks", landmark_seconds},
                         {"rigid", timings.rigid_seconds},
                         {"setup", timings.setup_seconds},
                         {"correspondences", timings.correspondence_seconds},
                         {"factorize", timings.factorize_seconds},
                         {"solve", timings.solve_seconds},
                         {"nonrigid_total", timings.total_seconds},
                         {"total", SecondsSince(start)}};
    WriteRegisterSet(options, rig, fit, report);
    std::printf("wrote %s: residual mean %.4f%% p95 %.4f%% max %.3f%% of the target diagonal; landmark rms %g; "
                "%.2f s\n",
                options.output.c_str(), fit.residual.mean_percent, fit.residual.p95_percent,
                fit.residual.max_percent, fit.landmark_rms, timings.total_seconds);
    return 0;
  } catch (const std::exception& error) {
    return Fail(error);
  }
}

}  // namespace

void AddLandmarksCommand(CLI::App& facerig, CommandBody& body) {
  const auto [landmarks, options] = AddSubcommand(facerig, body, "landmarks", "detect the 68 face landmarks on a mesh",
      "Detects dlib's 68 face landmarks on a mesh (OBJ, or a rig: .frig/.glb/template folder) and\n"
      "writes them as 3D points in the mesh's coordinates.",
      RunLandmarks);
  landmarks->add_option("mesh", options->mesh_path, "the mesh (OBJ or a rig)")->required();
  landmarks->add_option("--debug-png", options->debug_png, "draw the detection into this PNG");
  AddOutputOptions(*landmarks, options->output, options->report_path, "landmarks JSON to write");
  AddShapePredictorOption(*landmarks, options->params);
}

void AddRegisterCommand(CLI::App& facerig, CommandBody& body) {
  const auto [reg, options] = AddSubcommand(facerig, body, "register", "fit the template's neutral onto a target surface",
      "Fits the template's neutral onto the target surface (similarity alignment + optimal-step\n"
      "non-rigid ICP). The OBJ keeps the template's vertex order, in the target's coordinates.",
      RunRegister);
  reg->add_option("--template", options->template_path, "template: a rig or a folder of OBJs")->required();
  reg->add_option("--template-info", options->template_info_path, "the template's descriptor JSON (default: beside the rig, shipped, or derived)")
      ->check(CLI::ExistingFile);
  reg->add_option("--target", options->target_path, "the mesh to fit (OBJ or a rig)")->required();
  reg->add_option("--landmarks", options->landmarks_path, "the target's landmarks (default: detected)");
  AddOutputOptions(*reg, options->output, options->report_path, "fitted OBJ to write");
  AddShapePredictorOption(*reg, options->landmark_params);
}

}  // namespace facerig::cli
