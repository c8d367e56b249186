#include "cli_register.h"

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

#include "cli_common.h"
#include "cli_options.h"
#include "cli_template_info.h"
#include "facerig/offline/landmarks.h"
#include "facerig/offline/nonrigid_icp.h"
#include "facerig/offline/rasterizer.h"
#include "facerig/offline/error.h"
#include "facerig/offline/rig_build.h"
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

int RunLandmarks(const LandmarksOptions& options) {
  const auto& [mesh_path, output, debug_png, report_path, params] = options;
  try {
    const auto start = std::chrono::steady_clock::now();
    const RawRig mesh = LoadMeshForEditing(mesh_path);
    const double load_seconds = SecondsSince(start);
    std::fprintf(stderr, "%s: %zu vertices, %zu triangles (%.2f s to load); detecting landmarks...\n",
                 mesh_path.c_str(), mesh.positions.size(), mesh.triangles.size(), load_seconds);
    const auto model_start = std::chrono::steady_clock::now();
    LandmarkDetector detector(params);
    const double model_seconds = SecondsSince(model_start);
    const LandmarkResult result = detector.Detect(NeutralMesh(mesh));
    if (!debug_png.empty()) WritePng(debug_png, DrawLandmarks(result));
    WriteLandmarksJson(output, result.landmarks);
    std::printf(
        "wrote %s (68 landmarks; %d views tried, %d snapped off holes, %d eyes fitted to openings, detector score "
        "%.2f; %.3f s)\n",
        output.c_str(), result.views_tried, result.snapped, result.eyes_fitted, result.detector_score,
        result.seconds);
    if (!report_path.empty()) {
      nlohmann::json report;
      report["mesh"] = mesh_path;
      report["vertices"] = mesh.positions.size();
      report["views_tried"] = result.views_tried;
      report["eyes_fitted_to_openings"] = result.eyes_fitted;
      report["snapped"] = result.snapped;
      report["detector_score"] = result.detector_score;
      report["seconds"] = {{"load_mesh", load_seconds}, {"load_model", model_seconds}, {"detect", result.seconds}};
      WriteJsonAtomically(report_path, report);
    }
    return 0;
  } catch (const std::exception& error) {
    return Fail(error);
  }
}

int RunRegister(const RegisterOptions& options) {
  const auto& [template_path, target_path, output, landmarks_path, report_path, landmark_params,
               template_info_path] = options;
  try {
    const auto start = std::chrono::steady_clock::now();
    const Rig rig = LoadRigOrTemplateFolder(template_path);
    const RawRig target = LoadMeshForEditing(target_path);
    const double load_seconds = SecondsSince(start);
    std::fprintf(stderr, "template %zu vertices, target %zu vertices (%.2f s to load)\n", rig.vertex_count(),
                 target.positions.size(), load_seconds);

    std::optional<LandmarkDetector> detector;
    auto get_detector = [&]() -> LandmarkDetector& {
      if (!detector) detector.emplace(landmark_params);
      return *detector;
    };
    const auto landmark_start = std::chrono::steady_clock::now();
    FaceLandmarks target_landmarks;
    if (!landmarks_path.empty()) {
      target_landmarks = ReadLandmarksJson(landmarks_path);
    } else {
      std::fprintf(stderr, "detecting landmarks on the target...\n");
      target_landmarks = get_detector().Detect(NeutralMesh(target)).landmarks;
    }
    FaceTemplateInfo template_info = ResolveFaceTemplateInfo(rig, template_path, template_info_path);
    if (template_info.landmark_vertices.empty()) std::fprintf(stderr, "detecting landmarks on the template...\n");
    const std::vector<std::uint32_t> template_vertex_of = TemplateLandmarkVertices(rig, template_info, get_detector());
    PrintTemplateInfo(template_info);
    const RegistrationLandmarks landmarks = PairLandmarks(template_vertex_of, target_landmarks);
    const double landmark_seconds = SecondsSince(landmark_start);

    NonrigidIcpParams params;
    params.region_vertex_count = template_info.region.last + 1;
    std::fprintf(stderr, "rigid alignment and non-rigid ICP (%zu landmarks)...\n", landmarks.target_points.size());
    params.progress = [](std::size_t done, std::size_t total) { ProgressBar("non-rigid ICP", done, total); };
    const NonrigidIcpResult fit = NonrigidIcp(NeutralMesh(rig), NeutralMesh(target), landmarks, params);

    std::vector<glm::vec3> normals(fit.positions.size());
    ComputeVertexNormals(fit.positions, rig.triangles(), normals);
    WriteObj(output, fit.positions, normals, rig.uvs(), rig.triangles(), rig.parts());
    std::printf("wrote %s: residual mean %.4f%% p95 %.4f%% max %.3f%% of the target diagonal; landmark rms %g; "
                "%.2f s\n",
                output.c_str(), fit.residual.mean_percent, fit.residual.p95_percent, fit.residual.max_percent,
                fit.landmark_rms, fit.timings.total_seconds);
    if (!report_path.empty()) {
      nlohmann::json report;
      report["template"] = template_path;
      report["target"] = target_path;
      report["output"] = output;
      report["landmarks"] = landmarks_path.empty() ? "detected" : landmarks_path;
      report["template_info"] = TemplateInfoReport(template_info);
      report["residual_percent_of_diagonal"] = {{"mean", fit.residual.mean_percent},
                                                {"p95", fit.residual.p95_percent},
                                                {"max", fit.residual.max_percent}};
      report["target_diagonal"] = fit.residual.target_diagonal;
      report["measured_vertices"] = fit.residual.vertex_count;
      report["rejected_vertices"] = fit.residual.rejected_count;
      report["landmark_rms"] = fit.landmark_rms;
      report["rigid_scale"] = fit.rigid.scale;
      report["iterations_per_stage"] = fit.iterations_per_stage;
      report["factorizations"] = fit.factorizations;
      report["seconds"] = {{"load", load_seconds},
                           {"landmarks", landmark_seconds},
                           {"rigid", fit.timings.rigid_seconds},
                           {"setup", fit.timings.setup_seconds},
                           {"correspondences", fit.timings.correspondence_seconds},
                           {"factorize", fit.timings.factorize_seconds},
                           {"solve", fit.timings.solve_seconds},
                           {"nonrigid_total", fit.timings.total_seconds},
                           {"total", SecondsSince(start)}};
      WriteJsonAtomically(report_path, report);
    }
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
  landmarks->add_option("-o", options->output, "landmarks JSON to write")->required();
  landmarks->add_option("--debug-png", options->debug_png, "draw the detection into this PNG");
  landmarks->add_option("--json", options->report_path, "write a JSON report");
  landmarks->add_option("--shape-predictor", options->params.shape_predictor, "dlib 68-point shape predictor file");
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
  reg->add_option("-o", options->output, "fitted OBJ to write")->required();
  reg->add_option("--landmarks", options->landmarks_path, "the target's landmarks (default: detected)");
  reg->add_option("--json", options->report_path, "write a JSON report");
  reg->add_option("--shape-predictor", options->landmark_params.shape_predictor, "dlib 68-point shape predictor file");
}

}  // namespace facerig::cli
