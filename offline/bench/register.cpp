#include "cli/options.h"
#include "bench/register.h"
#include "bench/common.h"
#include "bench/json.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/registration/nonrigid_icp.h"
#include "measure/registration_targets.h"

namespace {

using Clock = std::chrono::steady_clock;

using facerig::SecondsSince;

double PeakResidentMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

double Mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

double Max(const std::vector<double>& values) {
  return values.empty() ? 0.0 : *std::max_element(values.begin(), values.end());
}

const char* UnitName(double units_per_cm) {
  return units_per_cm > 5.0 ? "mm" : (units_per_cm > 0.5 ? "cm" : "m");
}

struct LandmarkError {
  double no_jaw = 0.0;  // mean 3D error / inter-ocular distance, points 17-67
  double with_jaw = 0.0;  // all 68
};

LandmarkError MeasureLandmarks(const facerig::FaceLandmarks& detected, const facerig::test::RegistrationTarget& target) {
  const double interocular = static_cast<double>(glm::length(target.true_landmarks[36] - target.true_landmarks[45]));
  LandmarkError error;
  for (std::size_t k = 0; k < facerig::kDlibLandmarkCount; ++k) {
    const double e = static_cast<double>(glm::length(detected.points[k] - target.true_landmarks[k])) / interocular;
    error.with_jaw += e / 68.0;
    if (k >= 17) error.no_jaw += e / 51.0;
  }
  return error;
}

facerig::RegistrationLandmarks PairLandmarks(const facerig::test::IctFaceModel& ict,
                                             const facerig::FaceLandmarks& detected) {
  facerig::RegistrationLandmarks pairs;
  pairs.template_vertices = ict.info.landmark_vertices;
  pairs.target_points = detected.points;
  pairs.confidence = detected.confidence;
  return pairs;
}

// Fitted template vertex vs the true position of the same ICT vertex, face region, centimetres.
double CorrespondenceMeanCm(const facerig::test::IctFaceModel& ict, const facerig::NonrigidIcpResult& fit,
                            const facerig::test::RegistrationTarget& target) {
  double sum = 0.0;
  const std::uint32_t face = ict.face_vertex_count();
  for (std::uint32_t v = 0; v < face; ++v) {
    sum += static_cast<double>(glm::length(fit.positions[v] - target.true_ict_positions[v]));
  }
  return sum / face / target.units_per_cm;
}

void Progress(std::size_t done, std::size_t total) {
  std::fprintf(stderr, "\r  non-rigid ICP stage %zu/%zu", done, total);
  if (done >= total) std::fputc('\n', stderr);
  std::fflush(stderr);
}

struct Row {
  const char* name;
  double value;
  double target;  // upper limit
  const char* unit;
};

void PrintRow(const Row& row) {
  const bool pass = row.value <= row.target;
  std::printf("  %-44s %10.4f %-5s  target <= %-8g %s\n", row.name, row.value, row.unit, row.target,
              pass ? "ok" : "MISSED");
}

struct RegisterOptions {
  std::string ict_dir = FACERIG_DEFAULT_ICT_DIR;
  std::string json_path;
  int faces = 5;
  unsigned seed = 501;  // the tests use seeds below 200
  std::size_t target_vertices = 30000;
  std::size_t million_vertices = 1000000;
};

void AddRegisterOptions(CLI::App& app, RegisterOptions& options) {
  app.add_option("--ict", options.ict_dir, "the ICT-FaceKit folder");
  app.add_option("--faces", options.faces, "random faces (default 5)")->check(facerig::cli::InRange(1, 1000000));
  app.add_option("--seed", options.seed, "first random seed (default 501)");
  app.add_option("--target-vertices", options.target_vertices, "vertices of each re-meshed target (default 30000)");
  app.add_option("--million-vertices", options.million_vertices, "vertices of the large target (default 1000000)");
  std::size_t& million_vertices = options.million_vertices;
  app.add_flag_callback("--no-million", [&million_vertices] { million_vertices = 0; }, "skip the large target");
  app.add_option("--json", options.json_path, "write the results as JSON");
}

// One face's landmark and registration measures.
struct FaceResult {
  LandmarkError lm;
  double lm_cpu = 0.0;
  double corr = 0.0;
  double corr_truth = 0.0;  // the same registration from the true landmarks
  double cpu = 0.0;
};

// Every face's measures, one value per face.
struct FaceMeasures {
  std::vector<double> lm_no_jaw, lm_with_jaw, lm_seconds, lm_cpu_seconds, residual_mean, residual_p95,
      correspondence, correspondence_truth, fit_seconds, fit_cpu_seconds;
  nlohmann::json per_face = nlohmann::json::array();
};

void PrintFaceTableHeader() {
  std::printf("%-5s %7s %5s %8s %9s %9s %7s %7s %9s %9s %9s %9s %8s %8s\n", "seed", "verts", "unit", "rot deg",
              "lm noJaw", "lm jaw", "lm s", "lm cpu", "res mean%", "res p95%", "corr cm", "(true lm)", "fit s",
              "fit cpu");
}

// What both reports say of one landmarks + registration run (the keys sort
// on output, so their order here does not matter).
nlohmann::json RegistrationJson(const LandmarkError& lm, const facerig::LandmarkResult& detected,
                                const facerig::NonrigidIcpResult& fit, double correspondence_mean_cm) {
  return {{"landmark_seconds", detected.seconds},
          {"landmark_error_iod_no_jaw", lm.no_jaw},
          {"landmark_error_iod_with_jaw", lm.with_jaw},
          {"registration_seconds", fit.timings.total_seconds},
          {"residual_mean_percent", fit.residual.mean_percent},
          {"residual_p95_percent", fit.residual.p95_percent},
          {"correspondence_mean_cm", correspondence_mean_cm}};
}

nlohmann::json FaceJson(const facerig::test::RegistrationTargetOptions& options,
                        const facerig::test::RegistrationTarget& target, const facerig::LandmarkResult& detected,
                        const facerig::NonrigidIcpResult& fit, const FaceResult& r) {
  nlohmann::json json = RegistrationJson(r.lm, detected, fit, r.corr);
  json.update({{"seed", options.seed},
               {"target_vertices", target.positions.size()},
               {"units_per_cm", target.units_per_cm},
               {"rotation_degrees", target.rotation_degrees},
               {"landmark_cpu_seconds", r.lm_cpu},
               {"landmark_views_tried", detected.views_tried},
               {"residual_max_percent", fit.residual.max_percent},
               {"correspondence_mean_cm_true_landmarks", r.corr_truth},
               {"registration_cpu_seconds", r.cpu},
               {"seconds",
                {{"rigid", fit.timings.rigid_seconds},
                 {"setup", fit.timings.setup_seconds},
                 {"correspondences", fit.timings.correspondence_seconds},
                 {"factorize", fit.timings.factorize_seconds},
                 {"solve", fit.timings.solve_seconds}}}});
  return json;
}

// The measured part for one random face: landmarks, registration from them
// and from the true landmarks; prints its row and appends to `measures`.
void MeasureFace(facerig::LandmarkDetector& detector, const facerig::test::IctFaceModel& ict,
                 const facerig::NonrigidIcpParams& params, const facerig::test::RegistrationTargetOptions& options,
                 FaceMeasures& measures) {
  const facerig::test::RegistrationTarget target = facerig::test::MakeRegistrationTarget(ict, options);
  FaceResult r;
  const std::clock_t lm_cpu_start = std::clock();
  const facerig::LandmarkResult detected = detector.Detect(target.mesh());
  r.lm_cpu = CpuSecondsSince(lm_cpu_start);
  r.lm = MeasureLandmarks(detected.landmarks, target);

  const std::clock_t cpu_start = std::clock();
  const facerig::NonrigidIcpResult fit =
      facerig::NonrigidIcp(ict.mesh(), target.mesh(),
                           PairLandmarks(ict, detected.landmarks), params);
  r.cpu = CpuSecondsSince(cpu_start);
  r.corr = CorrespondenceMeanCm(ict, fit, target);
  // The same registration from the true landmark positions: how much of
  // the correspondence error the detected landmarks cause.
  facerig::FaceLandmarks truth = detected.landmarks;
  truth.points = target.true_landmarks;
  r.corr_truth = CorrespondenceMeanCm(
      ict,
      facerig::NonrigidIcp(ict.mesh(), target.mesh(),
                           PairLandmarks(ict, truth), params),
      target);

  measures.lm_no_jaw.push_back(r.lm.no_jaw);
  measures.lm_with_jaw.push_back(r.lm.with_jaw);
  measures.lm_seconds.push_back(detected.seconds);
  measures.lm_cpu_seconds.push_back(r.lm_cpu);
  measures.residual_mean.push_back(fit.residual.mean_percent);
  measures.residual_p95.push_back(fit.residual.p95_percent);
  measures.correspondence.push_back(r.corr);
  measures.correspondence_truth.push_back(r.corr_truth);
  measures.fit_seconds.push_back(fit.timings.total_seconds);
  measures.fit_cpu_seconds.push_back(r.cpu);
  std::printf("%-5u %7zu %5s %8.1f %9.4f %9.4f %7.3f %7.3f %9.4f %9.4f %9.3f %9.3f %8.2f %8.2f\n", options.seed,
              target.positions.size(), UnitName(target.units_per_cm), target.rotation_degrees, r.lm.no_jaw,
              r.lm.with_jaw, detected.seconds, r.lm_cpu, fit.residual.mean_percent, fit.residual.p95_percent, r.corr,
              r.corr_truth, fit.timings.total_seconds, r.cpu);
  measures.per_face.push_back(FaceJson(options, target, detected, fit, r));
}

// The means over the faces against their targets, with published timings
// for reference.
void PrintTargets(const FaceMeasures& m) {
  std::printf("\ntargets (mean over the faces; worst face in the JSON):\n");
  const Row rows[] = {
      {"landmark error / IOD, without jaw", Mean(m.lm_no_jaw), 0.03, ""},
      {"landmark error / IOD, with jaw", Mean(m.lm_with_jaw), 0.06, ""},
      {"landmark time per face (model loaded)", Mean(m.lm_seconds), 0.15, "s"},
      {"registration residual mean (% of diagonal)", Mean(m.residual_mean), 0.1, "%"},
      {"registration residual p95 (% of diagonal)", Mean(m.residual_p95), 0.5, "%"},
      {"correspondence error mean, face region", Mean(m.correspondence), 0.25, "cm"},
      {"  the same from the true landmarks", Mean(m.correspondence_truth), 0.25, "cm"},
      {"registration time, 11,248 vertices onto target", Mean(m.fit_seconds), 5.0, "s"},
  };
  for (const Row& row : rows) PrintRow(row);
  std::printf("  reference: published automatic 3D landmarking, 0.33 s per face\n"
              "  reference: published expression-transfer system, registration 2.7 s with a 1,138-vertex template\n"
              "  CPU time (all threads) per face: landmarks %.3f s, registration %.2f s; equal to the wall\n"
              "  times above when the process had its one core to itself\n",
              Mean(m.lm_cpu_seconds), Mean(m.fit_cpu_seconds));
}

nlohmann::json SummaryJson(const FaceMeasures& m) {
  auto summary = [](const std::vector<double>& values, double target) {
    return nlohmann::json{{"mean", Mean(values)}, {"max", Max(values)}, {"target", target}};
  };
  nlohmann::json json = {{"landmark_error_iod_no_jaw", summary(m.lm_no_jaw, 0.03)},
                         {"landmark_error_iod_with_jaw", summary(m.lm_with_jaw, 0.06)},
                         {"landmark_seconds", summary(m.lm_seconds, 0.15)},
                         {"landmark_cpu_seconds", summary(m.lm_cpu_seconds, 0.15)},
                         {"residual_mean_percent", summary(m.residual_mean, 0.1)},
                         {"residual_p95_percent", summary(m.residual_p95, 0.5)},
                         {"correspondence_mean_cm", summary(m.correspondence, 0.25)},
                         {"correspondence_mean_cm_true_landmarks", summary(m.correspondence_truth, 0.25)},
                         {"registration_seconds", summary(m.fit_seconds, 5.0)},
                         {"registration_cpu_seconds", summary(m.fit_cpu_seconds, 5.0)}};
  json["landmark_seconds"]["published"] = {{"seconds", 0.33},
                                           {"source", "automatic correspondence by render + 68 landmarks"}};
  json["registration_seconds"]["published"] = {
      {"seconds", 2.7}, {"template_vertices", 1138}, {"source", "Pawaskar et al., Expression Transfer"}};
  return json;
}

// A scan-sized target: the same pipeline must finish, in bounded memory.
nlohmann::json MeasureScan(facerig::LandmarkDetector& detector, const facerig::test::IctFaceModel& ict,
                           const facerig::NonrigidIcpParams& params, unsigned seed, std::size_t million_vertices) {
  std::printf("\nscan-sized target (%zu vertices):\n", million_vertices);
  facerig::test::RegistrationTargetOptions options;
  options.seed = seed + 1000;
  options.units_per_cm = 10.0;  // scans come in millimetres
  options.target_vertex_count = million_vertices;
  const auto make_start = Clock::now();
  const facerig::test::RegistrationTarget target = facerig::test::MakeRegistrationTarget(ict, options);
  const double make_seconds = SecondsSince(make_start);
  const double rss_before = PeakResidentMegabytes();
  const facerig::LandmarkResult detected = detector.Detect(target.mesh());
  const LandmarkError lm = MeasureLandmarks(detected.landmarks, target);
  facerig::NonrigidIcpParams scan_params = params;
  scan_params.progress = Progress;
  const facerig::NonrigidIcpResult fit =
      facerig::NonrigidIcp(ict.mesh(), target.mesh(), PairLandmarks(ict, detected.landmarks), scan_params);
  const double corr = CorrespondenceMeanCm(ict, fit, target);
  const double rss_after = PeakResidentMegabytes();
  const double mesh_megabytes =
      static_cast<double>(target.positions.size() * sizeof(glm::vec3) + target.triangles.size() * sizeof(facerig::Triangle)) /
      (1024.0 * 1024.0);
  std::printf("  %zu vertices, %zu triangles (%.0f MB as arrays; made in %.1f s)\n"
              "  landmarks %.2f s (error/IOD %.4f without jaw, %.4f with)\n"
              "  registration %.2f s (rigid %.2f, setup %.2f, correspondences %.2f, factorize %.2f, solve %.2f): "
              "residual mean %.4f%%, p95 %.4f%%, correspondence %.3f cm\n"
              "  peak resident memory %.0f MB before landmarks + registration, %.0f MB after\n",
              target.positions.size(), target.triangles.size(), mesh_megabytes, make_seconds, detected.seconds,
              lm.no_jaw, lm.with_jaw, fit.timings.total_seconds, fit.timings.rigid_seconds,
              fit.timings.setup_seconds, fit.timings.correspondence_seconds, fit.timings.factorize_seconds,
              fit.timings.solve_seconds, fit.residual.mean_percent, fit.residual.p95_percent, corr, rss_before,
              rss_after);
  nlohmann::json json = RegistrationJson(lm, detected, fit, corr);
  json.update({{"vertices", target.positions.size()},
               {"triangles", target.triangles.size()},
               {"mesh_megabytes", mesh_megabytes},
               {"peak_rss_megabytes_before", rss_before},
               {"peak_rss_megabytes_after", rss_after}});
  return json;
}

int BenchmarkRegistration(const RegisterOptions& settings) {
  nlohmann::json report;
  try {
    const auto load_start = Clock::now();
    const std::string& ict_dir = settings.ict_dir;
    const facerig::test::IctFaceModel ict = facerig::test::LoadIctFaces(ict_dir);
    const double ict_seconds = SecondsSince(load_start);
    const auto model_start = Clock::now();
    facerig::LandmarkDetector detector;
    const double model_seconds = SecondsSince(model_start);
    std::printf("template %s: %zu vertices, registered region %u (face %u); %d random re-meshed faces (seeds %u..), "
                "%zu target vertices, rotations up to 25 deg, units mm/cm/m in turn\n"
                "ICT read in %.2f s, dlib model loaded in %.2f s (not counted below)\n\n",
                settings.ict_dir.c_str(), ict.neutral.size(), ict.head_vertex_count(), ict.face_vertex_count(),
                settings.faces, settings.seed, settings.target_vertices, ict_seconds, model_seconds);

    facerig::NonrigidIcpParams params;
    params.region_vertex_count = ict.head_vertex_count();
    FaceMeasures measures;
    PrintFaceTableHeader();
    for (int f = 0; f < settings.faces; ++f) {
      facerig::test::RegistrationTargetOptions options;
      options.seed = settings.seed + static_cast<unsigned>(f);
      options.units_per_cm = kUnitCycle[f % 3];
      options.max_rotation_degrees = 25.0;
      options.target_vertex_count = settings.target_vertices;
      MeasureFace(detector, ict, params, options, measures);
    }
    PrintTargets(measures);
    report["template"] = settings.ict_dir;
    report["faces"] = settings.faces;
    report["first_seed"] = settings.seed;
    report["target_vertices"] = settings.target_vertices;
    report["model_load_seconds"] = model_seconds;
    report["per_face"] = measures.per_face;
    report["summary"] = SummaryJson(measures);
    if (settings.million_vertices > 0) {
      report["scan"] = MeasureScan(detector, ict, params, settings.seed, settings.million_vertices);
    }
  } catch (const std::exception& error) {
    return ReportBenchFailure(error);
  }
  std::printf("\nlandmark error: mean 3D distance to the ICT landmark vertices on the target / inter-ocular\n"
              "distance (outer eye corners); residual: fitted region vertex to target surface, %% of the\n"
              "target's bounding-box diagonal; correspondence: fitted face vertex vs the true position of the\n"
              "same ICT vertex. Times are wall clock on this machine (noisy when it is shared).\n");
  return WriteBenchJson(settings.json_path, report);
}

}  // namespace

int RunRegisterBenchmark(int argc, char** argv) {
  return ParseAndRunBench(argc, argv, "landmarks + registration of the ICT template onto re-meshed random ICT faces",
                          "facerig-bench register", AddRegisterOptions, BenchmarkRegistration);
}
