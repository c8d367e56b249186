#include "cli_options.h"
#include "bench_transfer.h"
#include "bench_json.h"

#include <algorithm>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "facerig/offline/deformation_transfer.h"
#include "facerig/offline/displacement_transfer.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/offline/io/template_folder.h"

namespace {

// ICT-FaceKit: the face region, vertices [0, 9409).
constexpr std::size_t kFaceLast = 9409;
constexpr int kIdentityModes = 20;
// Face and eye sockets, [0, 17039): the eyelid margins are in the sockets.
constexpr std::size_t kLidLast = 17039;

using Meshes = std::vector<std::vector<glm::vec3>>;

// neutral + sum_i w_i (identity_i - neutral), w_i ~ N(0, 1).
std::vector<glm::vec3> RandomIdentity(std::span<const glm::vec3> neutral, const Meshes& identities,
                                      std::mt19937& rng) {
  std::normal_distribution<float> normal(0.0f, 1.0f);
  std::vector<glm::vec3> face(neutral.begin(), neutral.end());
  for (const std::vector<glm::vec3>& identity : identities) {
    const float w = normal(rng);
    for (std::size_t v = 0; v < face.size(); ++v) face[v] += w * (identity[v] - neutral[v]);
  }
  return face;
}

struct ModeReport {
  std::string name;
  std::vector<double> errors;  // per shape, over all faces
  std::vector<double> leaks;
  std::vector<std::string> shape_of_error;
  // Per shape and face: sum (result - rest).(truth - rest) / sum |truth - rest|^2 over
  // the moved face vertices; above 1 the transfer overshoots the template's deltas.
  std::vector<double> amplitudes;
  double seconds = 0.0;        // per face, precompute + all shapes
  double factorize_seconds = 0.0;
  double precompute_seconds = 0.0;
  double cpu_seconds = 0.0;    // process CPU time (all threads), per face
  double blink_gap = 0.0;      // worst mean eyelid gap on eyeBlink_L/R / eye width
  double blink_crossing = 0.0;
};

void Measure(ModeReport& report, const facerig::Rig& rig, const Meshes& truth,
             const Meshes& result, std::span<const glm::vec3> target,
             const std::vector<facerig::EyelidMargins>& eyes, const std::vector<std::size_t>& blinks) {
  for (std::size_t s = 0; s < result.size(); ++s) {
    const facerig::ExpressionError e =
        facerig::MeasureExpressionError(target, truth[s], result[s], 0, kFaceLast);
    report.errors.push_back(e.relative_error);
    report.leaks.push_back(e.leak);
    report.shape_of_error.emplace_back(rig.shape_name(s));
    double largest2 = 0.0;
    for (std::size_t v = 0; v < kFaceLast; ++v) {
      const glm::dvec3 d = glm::dvec3(truth[s][v]) - glm::dvec3(target[v]);
      largest2 = std::max(largest2, d.x * d.x + d.y * d.y + d.z * d.z);
    }
    double along = 0.0;
    double norm2 = 0.0;
    for (std::size_t v = 0; v < kFaceLast; ++v) {
      const glm::dvec3 d = glm::dvec3(truth[s][v]) - glm::dvec3(target[v]);
      const double d2 = d.x * d.x + d.y * d.y + d.z * d.z;
      if (d2 <= 0.01 * largest2) continue;  // moved: > 10% of the largest displacement
      const glm::dvec3 r = glm::dvec3(result[s][v]) - glm::dvec3(target[v]);
      along += r.x * d.x + r.y * d.y + r.z * d.z;
      norm2 += d2;
    }
    report.amplitudes.push_back(norm2 > 0.0 ? along / norm2 : 1.0);
  }
  for (std::size_t i = 0; i < eyes.size(); ++i) {
    const facerig::EyelidGap gap = facerig::MeasureEyelidGap(result[blinks[i]], eyes[i]);
    report.blink_gap = std::max(report.blink_gap, gap.mean_gap);
    report.blink_crossing = std::max(report.blink_crossing, gap.max_crossing);
  }
}

}  // namespace

int RunTransferBenchmark(int argc, char** argv) {
#ifdef FACERIG_DEFAULT_ICT_DIR
  std::string ict_dir = FACERIG_DEFAULT_ICT_DIR;
#else
  std::string ict_dir = "../shared/data/ict-facekit";
#endif
  std::string json_path;
  int faces = 3;
  bool per_shape_table = false;
  unsigned seed = 1;
  facerig::DeformationTransferParams params;
  CLI::App app("deformation transfer / displacement matrices of the ICT rig onto random identities",
               "facerig-bench transfer");
  app.add_option("--ict", ict_dir, "the ICT-FaceKit folder");
  app.add_option("--faces", faces, "random identities (default 3)")->transform(CLI::Bound(1, 1000000));
  app.add_option("--seed", seed, "random seed (default 1)");
  app.add_option("--threads", params.threads, "solver threads")->transform(CLI::Bound(1, 1024));
  app.add_option("--static-threshold", params.static_threshold, "DeformationTransferParams::static_threshold");
  app.add_option("--still", params.still_fraction, "DeformationTransferParams::still_fraction");
  app.add_option("--contact", params.contact_weight, "DeformationTransferParams::contact_weight");
  app.add_flag("!--keep-contact-offset", params.close_contacts, "do not close contacts");
  app.add_option("--prior", params.displacement_prior, "DeformationTransferParams::displacement_prior");
  app.add_flag("--scaled-normal", params.scaled_normal, "DeformationTransferParams::scaled_normal");
  app.add_flag("--per-shape", per_shape_table, "print a table per shape");
  app.add_flag("!--no-area", params.area_weighted, "no area weighting");
  app.add_option("--json", json_path, "write the results as JSON");
  if (const std::optional<int> exit_code = facerig::cli::ParseCommandLine(app, argc - 1, argv + 1)) return *exit_code;

  facerig::Rig rig;
  Meshes identities;
  try {
    rig = facerig::ImportTemplateFolder(ict_dir);
    for (int k = 0; k < kIdentityModes; ++k) {
      char name[32];
      std::snprintf(name, sizeof(name), "identity%03d.obj", k);
      identities.push_back(facerig::ReadObj(std::filesystem::path(ict_dir) / name).positions);
      if (identities.back().size() != rig.vertex_count()) {
        std::fprintf(stderr, "facerig-bench: %s has the wrong vertex count\n", name);
        return 1;
      }
    }
  } catch (const facerig::IoError& error) {
    std::fprintf(stderr, "facerig-bench: %s\n", error.what());
    return 1;
  }
  const std::span<const glm::vec3> neutral = rig.positions();
  const Meshes expressions = facerig::RigExpressionMeshes(rig);
  const facerig::Mesh rig_mesh = facerig::NeutralMesh(rig);
  std::printf("template %s: %zu vertices, %zu triangles, %zu shapes; %d random identities (seed %u), "
              "%d threads\n",
              ict_dir.c_str(), rig.vertex_count(), rig.triangle_count(), rig.shape_count(), faces,
              seed, params.threads);

  // Eyelid margins (found on the template) for the blink check.
  std::vector<facerig::EyelidMargins> eyes;
  std::vector<std::size_t> blinks;
  for (const char* name : {"eyeBlink_L", "eyeBlink_R"}) {
    if (auto s = rig.FindShape(name)) {
      eyes.push_back(facerig::FindEyelidMargins(facerig::NeutralMesh(rig), expressions[*s], 0, kLidLast));
      blinks.push_back(*s);
    }
  }
  double template_gap = 0.0;
  double template_crossing = 0.0;
  for (std::size_t i = 0; i < eyes.size(); ++i) {
    const facerig::EyelidGap gap = facerig::MeasureEyelidGap(expressions[blinks[i]], eyes[i]);
    template_gap = std::max(template_gap, gap.mean_gap);
    template_crossing = std::max(template_crossing, gap.max_crossing);
  }

  std::vector<ModeReport> modes(7);
  modes[6].name = "mixed";
  modes[3].name = "displ-face";  // bounding box of the face region only
  modes[4].name = "displ-raw";   // no bounding-box normalisation
  modes[5].name = "truth";
  modes[0].name = "classic";
  modes[1].name = "identity";
  modes[2].name = "displacement";
  const facerig::DisplacementMatrices matrices = facerig::ComputeDisplacementMatrices(rig);
  std::mt19937 rng(seed);
  nlohmann::json report;
  std::size_t anchors = 0;
  std::size_t floating = 0;
  std::size_t regularized = 0;
  bool contacts_active = false;
  try {
    for (int f = 0; f < faces; ++f) {
      const std::vector<glm::vec3> target = RandomIdentity(neutral, identities, rng);
      Meshes truth(expressions.size());
      for (std::size_t s = 0; s < expressions.size(); ++s) {
        truth[s] = target;
        for (std::size_t v = 0; v < target.size(); ++v) truth[s][v] += expressions[s][v] - neutral[v];
      }
      Measure(modes[5], rig, truth, truth, target, eyes, blinks);
      Meshes previous;
      for (int m = 0; m < 2; ++m) {
        params.mode = m == 0 ? facerig::TransferMode::kClassic : facerig::TransferMode::kIdentityGradient;
        const std::clock_t cpu_start = std::clock();
        const facerig::DeformationTransferResult result =
            facerig::DeformationTransfer(rig_mesh, target, expressions, params);
        modes[static_cast<std::size_t>(m)].cpu_seconds +=
            static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC / faces;
        ModeReport& mode = modes[static_cast<std::size_t>(m)];
        mode.seconds += (result.precompute_seconds + result.solve_seconds) / faces;
        mode.factorize_seconds += result.factorize_seconds / faces;
        mode.precompute_seconds += result.precompute_seconds / faces;
        anchors = result.anchor_count;
        floating = result.floating_components;
        regularized = result.regularized_triangles;
        contacts_active = result.contacts_active;
        Measure(mode, rig, truth, result.expressions, target, eyes, blinks);
        if (m == 0) {
          previous = result.expressions;
        } else {
          for (std::size_t k = 0; k < previous.size(); ++k) {
            for (std::size_t v = 0; v < previous[k].size(); ++v) {
              previous[k][v] = 0.5f * (previous[k][v] + result.expressions[k][v]);
            }
          }
          Measure(modes[6], rig, truth, previous, target, eyes, blinks);
        }
      }
      // Same frame as the template (ICT identities are not posed): no rigid alignment.
      facerig::DisplacementTransferParams displacement_params;
      displacement_params.base_neutral.assign(neutral.begin(), neutral.end());
      displacement_params.align_model = false;
      const facerig::DisplacementTransferResult moved =
          facerig::TransferDisplacements(matrices, target, displacement_params);
      modes[2].seconds += moved.seconds / faces;
      Measure(modes[2], rig, truth, moved.poses, target, eyes, blinks);
      displacement_params.bounding_box_vertices.resize(kFaceLast);
      std::iota(displacement_params.bounding_box_vertices.begin(),
                displacement_params.bounding_box_vertices.end(), 0u);
      const facerig::DisplacementTransferResult face_box =
          facerig::TransferDisplacements(matrices, target, displacement_params);
      modes[3].seconds += face_box.seconds / faces;
      Measure(modes[3], rig, truth, face_box.poses, target, eyes, blinks);
      displacement_params.normalize_by_bounding_box = false;
      const facerig::DisplacementTransferResult raw =
          facerig::TransferDisplacements(matrices, target, displacement_params);
      modes[4].seconds += raw.seconds / faces;
      Measure(modes[4], rig, truth, raw.poses, target, eyes, blinks);
    }
  } catch (const std::exception& error) {
    std::fprintf(stderr, "facerig-bench: %s\n", error.what());
    return 1;
  }
  // Timing of the factorization alone (classic system, last face).
  std::printf("anchors %zu (static threshold %g of the diagonal), floating parts %zu, regularized "
              "triangles %zu\n",
              anchors, static_cast<double>(params.static_threshold), floating, regularized);
  const char* contacts = "closing";
  if (!contacts_active) {
    // Contacts need still pinning (one factorization per expression).
    contacts = params.contact_weight > 0.0 ? "off (they need still pinning)" : "off";
  } else if (!params.close_contacts) {
    contacts = "keeping the template's offset";
  }
  std::printf("still pinning %g, displacement prior %g, contacts %s\n\n", params.still_fraction,
              params.displacement_prior, contacts);
  std::printf("%-13s %8s %8s %8s %8s %9s %9s %9s %10s\n", "mode", "median", "p90", "max",
              "leak med", "leak p90", "blink gap", "crossing", "seconds");
  report["template"] = ict_dir;
  report["faces"] = faces;
  report["seed"] = seed;
  report["threads"] = params.threads;
  report["anchors"] = anchors;
  report["contacts_active"] = contacts_active;
  report["close_contacts"] = params.close_contacts;
  report["displacement_prior"] = params.displacement_prior;
  report["floating_parts"] = floating;
  report["regularized_triangles"] = regularized;
  report["template_blink_gap"] = template_gap;
  report["template_blink_crossing"] = template_crossing;
  for (const ModeReport& mode : modes) {
    const double median = facerig::Percentile(mode.errors, 0.5);
    const double p90 = facerig::Percentile(mode.errors, 0.9);
    const double worst = facerig::Percentile(mode.errors, 1.0);
    std::printf("%-13s %8.4f %8.4f %8.4f %8.4f %9.4f %9.4f %9.4f %10.3f\n", mode.name.c_str(),
                median, p90, worst, facerig::Percentile(mode.leaks, 0.5),
                facerig::Percentile(mode.leaks, 0.9), mode.blink_gap, mode.blink_crossing,
                mode.seconds);
    // Worst shapes (each shape's largest error over the faces).
    std::vector<std::pair<double, std::string>> by_shape;
    for (std::size_t i = 0; i < mode.errors.size(); ++i) {
      auto it = std::find_if(by_shape.begin(), by_shape.end(),
                             [&](const auto& e) { return e.second == mode.shape_of_error[i]; });
      if (it == by_shape.end()) {
        by_shape.emplace_back(mode.errors[i], mode.shape_of_error[i]);
      } else {
        it->first = std::max(it->first, mode.errors[i]);
      }
    }
    std::sort(by_shape.rbegin(), by_shape.rend());
    nlohmann::json worst_shapes = nlohmann::json::array();
    std::printf("    precompute %.3f s (factorization %.3f s), solves %.3f s, CPU %.3f s\n    worst:",
                mode.precompute_seconds, mode.factorize_seconds, mode.seconds - mode.precompute_seconds,
                mode.cpu_seconds);
    for (std::size_t i = 0; i < std::min<std::size_t>(5, by_shape.size()); ++i) {
      std::printf(" %s %.3f", by_shape[i].second.c_str(), by_shape[i].first);
      worst_shapes.push_back({{"shape", by_shape[i].second}, {"error", by_shape[i].first}});
    }
    std::printf("\n");
    nlohmann::json per_shape = nlohmann::json::object();
    for (const auto& [error, name] : by_shape) per_shape[name] = error;
    report["modes"][mode.name] = {{"median", median},
                                  {"p90", p90},
                                  {"max", worst},
                                  {"leak_median", facerig::Percentile(mode.leaks, 0.5)},
                                  {"leak_p90", facerig::Percentile(mode.leaks, 0.9)},
                                  {"blink_mean_gap", mode.blink_gap},
                                  {"blink_crossing", mode.blink_crossing},
                                  {"seconds_per_face", mode.seconds},
                                  {"precompute_seconds", mode.precompute_seconds},
                                  {"factorize_seconds", mode.factorize_seconds},
                                  {"cpu_seconds", mode.cpu_seconds},
                                  {"worst_shapes", worst_shapes},
                                  {"per_shape_worst", per_shape}};
  }
  if (per_shape_table) {
    // Each shape over the faces: median and largest error, median amplitude.
    std::printf("\n%-18s", "shape");
    for (std::size_t m : {0u, 1u, 6u}) {
      std::printf(" | %-8s %6s %6s %6s", modes[m].name.c_str(), "median", "max", "ampl");
    }
    std::printf("\n");
    const std::size_t shapes = rig.shape_count();
    for (std::size_t s = 0; s < shapes; ++s) {
      std::printf("%-18s", std::string(rig.shape_name(s)).c_str());
      for (std::size_t m : {0u, 1u, 6u}) {
        std::vector<double> errors;
        std::vector<double> amplitudes;
        for (std::size_t i = s; i < modes[m].errors.size(); i += shapes) {
          errors.push_back(modes[m].errors[i]);
          amplitudes.push_back(modes[m].amplitudes[i]);
        }
        std::printf(" | %-8s %6.3f %6.3f %6.3f", "", facerig::Percentile(errors, 0.5),
                    facerig::Percentile(errors, 1.0), facerig::Percentile(amplitudes, 0.5));
      }
      std::printf("\n");
    }
  }
  std::printf("\nerror: mean |result - truth| / mean |truth - rest| over the face vertices each shape\n"
              "moves (> 10%% of its largest displacement); leak: mean motion of those it leaves still\n"
              "(< 1%%) over the same mean. blink gap: mean distance of the upper lid margin vertices\n"
              "to the lower margin polyline / eye width on eyeBlink_L/R, worst eye and face; crossing:\n"
              "deepest upper vertex below that polyline (template: gap %.4f, crossing %.4f;\n"
              "truth = target neutral + template deltas). seconds: precompute\n"
              "(factorization) + all %zu shapes; CPU: all threads. displacement: paper 002 with the\n"
              "whole-mesh box ratio; displ-face: the face region's box; displ-raw: no normalisation\n"
              "(the additive ground truth itself); mixed: mean of classic and identity results.\n"
              "--per-shape: each shape's median and largest error over the faces, and its median\n"
              "amplitude, sum (result - rest).(truth - rest) / sum |truth - rest|^2 over the moved\n"
              "face vertices (> 1: larger motion than the template's deltas).\n",
              template_gap, template_crossing, rig.shape_count());
  return WriteBenchJson(json_path, report);
}
