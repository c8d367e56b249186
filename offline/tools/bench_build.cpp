#include "cli_options.h"
#include "bench_build.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_json.h"
#include "facerig/offline/deformation_transfer.h"
#include "facerig/offline/landmarks.h"
#include "facerig/offline/rig_build.h"
#include "facerig/offline/io/template_folder.h"
#include "support/registration_targets.h"

namespace {

using Clock = std::chrono::steady_clock;

using facerig::cli::SecondsSince;

void PrintCheck(const char* what, double value, const char* comparison, double target) {
  const bool ok = value <= target;
  std::printf("  %-50s %8.4f   target %s %-6g %s\n", what, value, comparison, target, ok ? "ok" : "MISSED");
}

}  // namespace

int RunBuildBenchmark(int argc, char** argv) {
#ifdef FACERIG_DEFAULT_ICT_DIR
  std::string ict_dir = FACERIG_DEFAULT_ICT_DIR;
#else
  std::string ict_dir = "../shared/data/ict-facekit";
#endif
  std::string json_path;
  int faces = 3;
  unsigned seed = 601;  // the tests use seeds below 200, bench register 501..
  std::size_t target_vertices = 30000;
  CLI::App app("the whole facerig build on re-meshed random ICT faces, each mode", "facerig-bench build");
  app.add_option("--ict", ict_dir, "the ICT-FaceKit folder");
  app.add_option("--faces", faces, "random faces (default 3)")->transform(CLI::Bound(1, 1000000));
  app.add_option("--seed", seed, "first random seed (default 601)");
  app.add_option("--target-vertices", target_vertices, "vertices of each re-meshed target (default 30000)");
  app.add_option("--json", json_path, "write the results as JSON");
  if (const std::optional<int> exit_code = facerig::cli::ParseCommandLine(app, argc - 1, argv + 1)) return *exit_code;

  nlohmann::json report;
  try {
    const auto load_start = Clock::now();
    const facerig::Rig ict = facerig::ImportTemplateFolder(ict_dir);
    const facerig::test::IctFaceModel model = facerig::test::LoadIctFaces(ict_dir);
    const double load_seconds = SecondsSince(load_start);
    const auto detector_start = Clock::now();
    facerig::LandmarkDetector detector;
    const double detector_seconds = SecondsSince(detector_start);
    std::printf("template %s: %zu vertices, %zu shapes; %d random re-meshed faces (seeds %u..) of %zu vertices;\n"
                "ICT read in %.2f s, dlib model loaded in %.2f s (both once, not counted below)\n\n",
                ict_dir.c_str(), ict.vertex_count(), ict.shape_count(), faces, seed, target_vertices, load_seconds,
                detector_seconds);
    std::printf("%-5s %6s %4s  %6s %6s %6s %6s %7s  %-12s %-12s %-12s\n", "seed", "verts", "unit", "lm s", "reg s",
                "dt s", "map s", "total s", "classic", "identity", "displacement");
    std::printf("%49s %-12s %-12s %-12s\n", "", "med/p90", "med/p90", "med/p90");

    constexpr facerig::BuildMode kModes[3] = {facerig::BuildMode::kClassic, facerig::BuildMode::kIdentityGradient,
                                              facerig::BuildMode::kDisplacement};
    std::vector<double> totals;
    std::vector<double> medians[3], p90s[3], leaks[3];
    nlohmann::json per_face = nlohmann::json::array();
    for (int f = 0; f < faces; ++f) {
      facerig::test::RegistrationTargetOptions options;
      options.seed = seed + static_cast<unsigned>(f);
      options.target_vertex_count = target_vertices;
      static constexpr double kUnits[3] = {10.0, 1.0, 0.01};
      options.units_per_cm = kUnits[f % 3];
      const facerig::test::RegistrationTarget target = facerig::test::MakeRegistrationTarget(model, options);
      facerig::RawRig target_rig;
      target_rig.positions = target.positions;
      target_rig.triangles = target.triangles;

      // What `facerig build` does after loading: landmarks, then the pipeline.
      const auto start = Clock::now();
      const facerig::LandmarkResult detected = detector.Detect(target.positions, target.triangles);
      const double landmark_seconds = SecondsSince(start);
      const facerig::RegistrationLandmarks pairs =
          facerig::PairLandmarks(facerig::IctLandmarkVertices(), detected.landmarks);
      const facerig::BuildRigResult classic = facerig::BuildRig(ict, target_rig, pairs);
      const facerig::Rig classic_rig = facerig::RigBuilder::Build(classic.rig).value();
      const double total_seconds = SecondsSince(start);
      totals.push_back(total_seconds);

      nlohmann::json face = {{"seed", options.seed},
                             {"vertices", target.positions.size()},
                             {"units_per_cm", options.units_per_cm},
                             {"seconds",
                              {{"landmarks", landmark_seconds},
                               {"registration", classic.timings.registration_seconds},
                               {"transfer", classic.timings.transfer_seconds},
                               {"map", classic.timings.mapping_seconds},
                               {"total", total_seconds}}}};
      std::string columns;
      for (int m = 0; m < 3; ++m) {
        facerig::BuildRigParams params;
        params.mode = kModes[m];
        std::optional<facerig::Rig> other;
        if (m > 0) {
          other = facerig::RigBuilder::Build(
              facerig::BuildRigOnRegistration(ict, target_rig, classic.registration, params).rig);
        }
        const facerig::test::BuiltRigErrors errors =
            facerig::test::MeasureBuiltRig(model, ict, target, m == 0 ? classic_rig : other.value());
        const double median = facerig::Percentile(errors.relative, 0.5);
        const double p90 = facerig::Percentile(errors.relative, 0.9);
        const double leak = facerig::Percentile(errors.leak, 0.5);
        medians[m].push_back(median);
        p90s[m].push_back(p90);
        leaks[m].push_back(leak);
        face[facerig::ToString(kModes[m])] = {{"median", median}, {"p90", p90}, {"leak_median", leak}};
        char cell[32];
        std::snprintf(cell, sizeof(cell), "%.3f/%.3f", median, p90);
        columns += std::string(cell) + std::string(13 - std::min<std::size_t>(12, std::string(cell).size()), ' ');
      }
      const char* unit = options.units_per_cm == 10.0 ? "mm" : options.units_per_cm == 1.0 ? "cm" : "m";
      std::printf("%-5u %6zu %4s  %6.3f %6.2f %6.2f %6.2f %7.2f  %s\n", options.seed, target.positions.size(), unit,
                  landmark_seconds, classic.timings.registration_seconds, classic.timings.transfer_seconds,
                  classic.timings.mapping_seconds, total_seconds, columns.c_str());
      per_face.push_back(face);
    }
    report["faces"] = per_face;
    std::printf("\n");
    for (int m = 0; m < 3; ++m) {
      const std::string mode = facerig::ToString(kModes[m]);
      const double median = facerig::Percentile(medians[m], 0.5);
      const double p90 = facerig::Percentile(p90s[m], 0.5);
      const double leak = facerig::Percentile(leaks[m], 1.0);
      PrintCheck((mode + ": relative error median (median face)").c_str(), median, "<=", 0.10);
      PrintCheck((mode + ": relative error p90 (median face)").c_str(), p90, "<=", 0.20);
      PrintCheck((mode + ": leak median (worst face)").c_str(), leak, "<=", 0.02);
      report["summary"][mode] = {{"median", median}, {"p90", p90}, {"leak", leak}};
    }
    const double worst_total = *std::max_element(totals.begin(), totals.end());
    PrintCheck("whole build, landmarks to output rig (worst, s)", worst_total, "<=", 10.0);
    report["summary"]["worst_total_seconds"] = worst_total;
    std::printf("  reference: displacement matrices (paper 002) are the baseline column; the issue's plain\n"
                "  deformation transfer on same-topology faces: median 0.055-0.064, p90 0.075-0.11\n");
  } catch (const std::exception& error) {
    std::fprintf(stderr, "facerig-bench: %s\n", error.what());
    return 1;
  }
  std::printf("\nrelative error: over the target vertices on ICT's face region that an expression moves, mean\n"
              "|result - truth| / mean |truth - rest|; truth from the known random face + ICT's delta. Times are\n"
              "wall clock (noisy when the machine is shared); the ICT import and the dlib model load are once.\n");
  return WriteBenchJson(json_path, report);
}
