#include "cli/options.h"
#include "bench/transfer.h"
#include "bench/common.h"
#include "bench/json.h"

#include <algorithm>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numeric>
#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "facerig/offline/openings/gaps.h"
#include "facerig/offline/transfer/deformation_transfer.h"
#include "facerig/offline/transfer/displacement_transfer.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/offline/io/template_folder.h"
#include "measure/expression_error.h"
#include "measure/ict_vertex_ranges.h"

namespace {

namespace ict = facerig::test::ict;
constexpr int kIdentityModes = 20;

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
             const std::vector<facerig::OpeningMargins>& eyes, const std::vector<std::size_t>& blinks) {
  for (std::size_t s = 0; s < result.size(); ++s) {
    const facerig::ExpressionError e =
        facerig::MeasureExpressionError(target, truth[s], result[s], 0, ict::kFace.end);
    report.errors.push_back(e.relative_error);
    report.leaks.push_back(e.leak);
    report.shape_of_error.emplace_back(rig.shape_name(s));
    double largest2 = 0.0;
    for (std::size_t v = 0; v < ict::kFace.end; ++v) {
      const glm::dvec3 d = glm::dvec3(truth[s][v]) - glm::dvec3(target[v]);
      largest2 = std::max(largest2, d.x * d.x + d.y * d.y + d.z * d.z);
    }
    double along = 0.0;
    double norm2 = 0.0;
    for (std::size_t v = 0; v < ict::kFace.end; ++v) {
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
    const facerig::OpeningGap gap = facerig::MeasureOpeningGap(result[blinks[i]], eyes[i]);
    report.blink_gap = std::max(report.blink_gap, gap.mean_gap);
    report.blink_crossing = std::max(report.blink_crossing, gap.max_crossing);
  }
}

struct TransferOptions {
  std::string ict_dir = FACERIG_DEFAULT_ICT_DIR;
  std::string json_path;
  int faces = 3;
  bool per_shape_table = false;
  unsigned seed = 1;
  facerig::DeformationTransferParams params;
};

void AddTransferOptions(CLI::App& app, TransferOptions& options) {
  facerig::DeformationTransferParams& params = options.params;
  app.add_option("--ict", options.ict_dir, "the ICT-FaceKit folder");
  app.add_option("--faces", options.faces, "random identities (default 3)")->check(facerig::cli::InRange(1, 1000000));
  app.add_option("--seed", options.seed, "random seed (default 1)");
  app.add_option("--threads", params.threads, "solver threads")->check(facerig::cli::InRange(1, 1024));
  app.add_option("--static-threshold", params.static_threshold, "DeformationTransferParams::static_threshold");
  app.add_option("--still", params.still_fraction, "DeformationTransferParams::still_fraction");
  app.add_option("--contact", params.contact_weight, "DeformationTransferParams::contact_weight");
  facerig::cli::AddOffFlag(app, "--keep-contact-offset", params.close_contacts, "do not close contacts");
  app.add_option("--prior", params.displacement_prior, "DeformationTransferParams::displacement_prior");
  app.add_flag("--scaled-normal", params.scaled_normal, "DeformationTransferParams::scaled_normal");
  app.add_flag("--per-shape", options.per_shape_table, "print a table per shape");
  facerig::cli::AddOffFlag(app, "--no-area", params.area_weighted, "no area weighting");
  app.add_option("--json", options.json_path, "write the results as JSON");
}

// The template rig and its identity modes; false after printing why not.
bool LoadTemplate(const std::string& ict_dir, facerig::Rig& rig, Meshes& identities) {
  try {
    rig = facerig::ImportTemplateFolder(ict_dir);
    for (int k = 0; k < kIdentityModes; ++k) {
      char name[32];
      std::snprintf(name, sizeof(name), "identity%03d.obj", k);
      identities.push_back(facerig::ReadObj(std::filesystem::path(ict_dir) / name).positions);
      if (identities.back().size() != rig.vertex_count()) {
        std::fprintf(stderr, "facerig-bench: %s has the wrong vertex count\n", name);
        return false;
      }
    }
  } catch (const facerig::IoError& error) {
    ReportBenchFailure(error);
    return false;
  }
  return true;
}

// Eyelid margins (found on the template) for the blink check, and the
// template's own blink as the reference.
struct BlinkCheck {
  std::vector<facerig::OpeningMargins> eyes;
  std::vector<std::size_t> blinks;  // the eyeBlink_L/R shape of each eye
  double template_gap = 0.0;
  double template_crossing = 0.0;
};

BlinkCheck FindBlinkCheck(const facerig::Rig& rig, const Meshes& expressions) {
  BlinkCheck check;
  std::vector<facerig::OpeningMargins>& eyes = check.eyes;
  std::vector<std::size_t>& blinks = check.blinks;
  for (const char* name : {"eyeBlink_L", "eyeBlink_R"}) {
    if (auto s = rig.FindShape(name)) {
      eyes.push_back(facerig::FindEyelidMargins(facerig::NeutralMesh(rig), expressions[*s], 0, ict::kBeforeTeeth.end));
      blinks.push_back(*s);
    }
  }
  for (std::size_t i = 0; i < eyes.size(); ++i) {
    const facerig::OpeningGap gap = facerig::MeasureOpeningGap(expressions[blinks[i]], eyes[i]);
    check.template_gap = std::max(check.template_gap, gap.mean_gap);
    check.template_crossing = std::max(check.template_crossing, gap.max_crossing);
  }
  return check;
}

// Indices into the mode list; the table prints in this order.
enum ModeIndex : std::size_t { kClassic, kIdentity, kDisplacement, kDisplFace, kDisplRaw, kTruth, kMixed, kModeCount };

std::vector<ModeReport> MakeModes() {
  std::vector<ModeReport> modes(kModeCount);
  modes[kMixed].name = "mixed";
  modes[kDisplFace].name = "displ-face";  // bounding box of the face region only
  modes[kDisplRaw].name = "displ-raw";    // no bounding-box normalisation
  modes[kTruth].name = "truth";
  modes[kClassic].name = "classic";
  modes[kIdentity].name = "identity";
  modes[kDisplacement].name = "displacement";
  return modes;
}

// The solver's structure on the last face (the same for every face).
struct SolverFacts {
  std::size_t anchors = 0;
  std::size_t floating = 0;
  std::size_t regularized = 0;
  bool contacts_active = false;
};

// One random face: its neutral and the additive ground truth of every expression.
struct Face {
  std::vector<glm::vec3> target;
  Meshes truth;
};

Face MakeFace(std::span<const glm::vec3> neutral, const Meshes& identities, const Meshes& expressions,
              std::mt19937& rng) {
  Face face{RandomIdentity(neutral, identities, rng), Meshes(expressions.size())};
  for (std::size_t s = 0; s < expressions.size(); ++s) {
    face.truth[s] = face.target;
    for (std::size_t v = 0; v < face.target.size(); ++v) face.truth[s][v] += expressions[s][v] - neutral[v];
  }
  return face;
}

// Classic and identity-gradient deformation transfer onto one face, and the
// mean of the two; each timed and measured.
void RunDeformationTransfers(std::vector<ModeReport>& modes, SolverFacts& facts, const facerig::Rig& rig,
                             const Meshes& expressions, const Face& face,
                             const BlinkCheck& check, facerig::DeformationTransferParams params, int faces) {
  const std::vector<glm::vec3>& target = face.target;
  const facerig::Mesh source = facerig::NeutralMesh(rig);
  Meshes previous;
  for (int m = 0; m < 2; ++m) {
    params.mode = m == 0 ? facerig::TransferMode::kClassic : facerig::TransferMode::kIdentityGradient;
    const std::clock_t cpu_start = std::clock();
    const facerig::DeformationTransferResult result =
        facerig::DeformationTransfer(source, target, expressions, params);
    modes[static_cast<std::size_t>(m)].cpu_seconds += CpuSecondsSince(cpu_start) / faces;
    ModeReport& mode = modes[static_cast<std::size_t>(m)];
    mode.seconds += (result.precompute_seconds + result.solve_seconds) / faces;
    mode.factorize_seconds += result.factorize_seconds / faces;
    mode.precompute_seconds += result.precompute_seconds / faces;
    facts = {result.anchor_count, result.floating_components, result.regularized_triangles, result.contacts_active};
    Measure(mode, rig, face.truth, result.expressions, target, check.eyes, check.blinks);
    if (m == 0) {
      previous = result.expressions;
    } else {
      for (std::size_t k = 0; k < previous.size(); ++k) {
        for (std::size_t v = 0; v < previous[k].size(); ++v) {
          previous[k][v] = 0.5f * (previous[k][v] + result.expressions[k][v]);
        }
      }
      Measure(modes[kMixed], rig, face.truth, previous, target, check.eyes, check.blinks);
    }
  }
}

// Displacement matrices onto one face: whole-mesh box, face-region box, no box.
void RunDisplacementTransfers(std::vector<ModeReport>& modes, const facerig::Rig& rig,
                              std::span<const glm::vec3> neutral, const facerig::DisplacementMatrices& matrices,
                              const Face& face, const BlinkCheck& check, int faces) {
  const std::vector<glm::vec3>& target = face.target;
  // Same frame as the template (ICT identities are not posed): no rigid alignment.
  facerig::DisplacementTransferParams displacement_params;
  displacement_params.base_neutral.assign(neutral.begin(), neutral.end());
  displacement_params.align_model = false;
  const facerig::DisplacementTransferResult moved =
      facerig::TransferDisplacements(matrices, target, displacement_params);
  modes[kDisplacement].seconds += moved.seconds / faces;
  Measure(modes[kDisplacement], rig, face.truth, moved.poses, target, check.eyes, check.blinks);
  displacement_params.bounding_box_vertices.resize(ict::kFace.end);
  std::iota(displacement_params.bounding_box_vertices.begin(),
            displacement_params.bounding_box_vertices.end(), 0u);
  const facerig::DisplacementTransferResult face_box =
      facerig::TransferDisplacements(matrices, target, displacement_params);
  modes[kDisplFace].seconds += face_box.seconds / faces;
  Measure(modes[kDisplFace], rig, face.truth, face_box.poses, target, check.eyes, check.blinks);
  displacement_params.normalize_by_bounding_box = false;
  const facerig::DisplacementTransferResult raw =
      facerig::TransferDisplacements(matrices, target, displacement_params);
  modes[kDisplRaw].seconds += raw.seconds / faces;
  Measure(modes[kDisplRaw], rig, face.truth, raw.poses, target, check.eyes, check.blinks);
}

void PrintSolverFacts(const SolverFacts& facts, const facerig::DeformationTransferParams& params) {
  std::printf("anchors %zu (static threshold %g of the diagonal), floating parts %zu, regularized "
              "triangles %zu\n",
              facts.anchors, static_cast<double>(params.static_threshold), facts.floating, facts.regularized);
  const char* contacts = "closing";
  if (!facts.contacts_active) {
    // Contacts need still pinning (one factorization per expression).
    contacts = params.contact_weight > 0.0 ? "off (they need still pinning)" : "off";
  } else if (!params.close_contacts) {
    contacts = "keeping the template's offset";
  }
  std::printf("still pinning %g, displacement prior %g, contacts %s\n\n", params.still_fraction,
              params.displacement_prior, contacts);
}

// Each shape's largest error over the faces, largest first.
std::vector<std::pair<double, std::string>> WorstErrorPerShape(const ModeReport& mode) {
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
  return by_shape;
}

// Prints one mode's row, its timing line and worst shapes; returns its JSON.
nlohmann::json ReportMode(const ModeReport& mode) {
  const double median = facerig::Percentile(mode.errors, 0.5);
  const double p90 = facerig::Percentile(mode.errors, 0.9);
  const double worst = facerig::Percentile(mode.errors, 1.0);
  std::printf("%-13s %8.4f %8.4f %8.4f %8.4f %9.4f %9.4f %9.4f %10.3f\n", mode.name.c_str(),
              median, p90, worst, facerig::Percentile(mode.leaks, 0.5),
              facerig::Percentile(mode.leaks, 0.9), mode.blink_gap, mode.blink_crossing,
              mode.seconds);
  const std::vector<std::pair<double, std::string>> by_shape = WorstErrorPerShape(mode);
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
  return {{"median", median},
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

// Each shape over the faces: median and largest error, median amplitude.
void PrintPerShapeTable(const facerig::Rig& rig, const std::vector<ModeReport>& modes) {
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

void PrintLegend(const BlinkCheck& check, std::size_t shape_count) {
  std::printf("\nerror: mean |result - truth| / mean |truth - rest| over the face vertices each shape\n"
              "moves (> 10%% of its largest displacement); leak: mean motion of those it leaves still\n"
              "(< 1%%) over the same mean. blink gap: mean distance of the upper lid margin vertices\n"
              "to the lower margin polyline / eye width on eyeBlink_L/R, worst eye and face; crossing:\n"
              "deepest upper vertex below that polyline (template: gap %.4f, crossing %.4f;\n"
              "truth = target neutral + template deltas). seconds: precompute\n"
              "(factorization) + all %zu shapes; CPU: all threads. displacement: displacement matrices\n"
              "with the whole-mesh box ratio; displ-face: the face region's box; displ-raw: no normalisation\n"
              "(the additive ground truth itself); mixed: mean of classic and identity results.\n"
              "--per-shape: each shape's median and largest error over the faces, and its median\n"
              "amplitude, sum (result - rest).(truth - rest) / sum |truth - rest|^2 over the moved\n"
              "face vertices (> 1: larger motion than the template's deltas).\n",
              check.template_gap, check.template_crossing, shape_count);
}

nlohmann::json RunHeaderJson(const TransferOptions& options, const SolverFacts& facts, const BlinkCheck& check) {
  nlohmann::json report;
  report["template"] = options.ict_dir;
  report["faces"] = options.faces;
  report["seed"] = options.seed;
  report["threads"] = options.params.threads;
  report["anchors"] = facts.anchors;
  report["contacts_active"] = facts.contacts_active;
  report["close_contacts"] = options.params.close_contacts;
  report["displacement_prior"] = options.params.displacement_prior;
  report["floating_parts"] = facts.floating;
  report["regularized_triangles"] = facts.regularized;
  report["template_blink_gap"] = check.template_gap;
  report["template_blink_crossing"] = check.template_crossing;
  return report;
}

int BenchmarkTransfer(const TransferOptions& options) {
  const facerig::DeformationTransferParams& params = options.params;

  facerig::Rig rig;
  Meshes identities;
  if (!LoadTemplate(options.ict_dir, rig, identities)) return 1;
  const std::span<const glm::vec3> neutral = rig.positions();
  const Meshes expressions = facerig::RigExpressionMeshes(rig);
  std::printf("template %s: %zu vertices, %zu triangles, %zu shapes; %d random identities (seed %u), "
              "%d threads\n",
              options.ict_dir.c_str(), rig.vertex_count(), rig.triangle_count(), rig.shape_count(), options.faces,
              options.seed, params.threads);
  const BlinkCheck check = FindBlinkCheck(rig, expressions);

  std::vector<ModeReport> modes = MakeModes();
  const facerig::DisplacementMatrices matrices = facerig::ComputeDisplacementMatrices(rig);
  std::mt19937 rng(options.seed);
  SolverFacts facts;
  try {
    for (int f = 0; f < options.faces; ++f) {
      const Face face = MakeFace(neutral, identities, expressions, rng);
      Measure(modes[kTruth], rig, face.truth, face.truth, face.target, check.eyes, check.blinks);
      RunDeformationTransfers(modes, facts, rig, expressions, face, check, params, options.faces);
      RunDisplacementTransfers(modes, rig, neutral, matrices, face, check, options.faces);
    }
  } catch (const std::exception& error) {
    return ReportBenchFailure(error);
  }
  PrintSolverFacts(facts, params);
  std::printf("%-13s %8s %8s %8s %8s %9s %9s %9s %10s\n", "mode", "median", "p90", "max",
              "leak med", "leak p90", "blink gap", "crossing", "seconds");
  nlohmann::json report = RunHeaderJson(options, facts, check);
  for (const ModeReport& mode : modes) report["modes"][mode.name] = ReportMode(mode);
  if (options.per_shape_table) PrintPerShapeTable(rig, modes);
  PrintLegend(check, rig.shape_count());
  return WriteBenchJson(options.json_path, report);
}

}  // namespace

int RunTransferBenchmark(int argc, char** argv) {
  return ParseAndRunBench(argc, argv,
                          "deformation transfer / displacement matrices of the ICT rig onto random identities",
                          "facerig-bench transfer", AddTransferOptions, BenchmarkTransfer);
}
