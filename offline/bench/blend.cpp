#include "cli/options.h"
#include "bench/blend.h"
#include "bench/common.h"
#include "bench/json.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "measure/dense_blend.h"
#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/shape_names.h"
#include "facerig/offline/io/template_folder.h"
#include "measure/allocation_counter.h"

namespace {

using Clock = std::chrono::steady_clock;

// Median microseconds of `body` over repeated runs (about 0.25 s in all).
template <typename Body>
double MedianMicroseconds(Body&& body) {
  body();  // warm caches
  std::vector<double> samples;
  const auto budget_end = Clock::now() + std::chrono::milliseconds(250);
  while (samples.size() < 2000 && (samples.size() < 15 || Clock::now() < budget_end)) {
    const auto start = Clock::now();
    body();
    samples.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
  }
  return UpperMedian(std::move(samples));
}

struct Workload {
  std::string name;
  std::vector<float> weights;
};

// Shapes a speech frame drives (viseme mouth shapes, both sides).
constexpr const char* kSpeechShapes[] = {
    "jawOpen", "mouthClose", "mouthFunnel", "mouthPucker", "mouthSmile_L", "mouthSmile_R",
    "mouthStretch_L", "mouthStretch_R", "mouthLowerDown_L", "mouthLowerDown_R",
    "mouthUpperUp_L", "mouthUpperUp_R"};

std::vector<Workload> MakeWorkloads(const facerig::Rig& rig) {
  const std::size_t n = rig.shape_count();
  std::vector<Workload> workloads;
  Workload one{"one", std::vector<float>(n, 0.0f)};
  const std::vector<std::size_t> jaw = facerig::FindShapesByArkitName(rig, "jawOpen");
  one.weights[jaw.empty() ? 0 : jaw.front()] = 0.7f;
  workloads.push_back(one);

  Workload speech{"speech12", std::vector<float>(n, 0.0f)};
  std::size_t active = 0;
  for (const char* name : kSpeechShapes) {
    for (std::size_t s : facerig::FindShapesByArkitName(rig, name)) {
      speech.weights[s] = 0.1f + 0.07f * static_cast<float>(active++);
    }
  }
  // Rigs without ARKit names: the first 12 shapes.
  for (std::size_t s = 0; active < 12 && s < n; ++s) {
    if (speech.weights[s] == 0.0f) speech.weights[s] = 0.1f + 0.07f * static_cast<float>(active++);
  }
  workloads.push_back(speech);

  Workload all{"all" + std::to_string(n), std::vector<float>(n, 0.0f)};
  for (std::size_t s = 0; s < n; ++s) all.weights[s] = 0.05f + 0.9f * static_cast<float>(s % 7) / 7.0f;
  workloads.push_back(all);
  return workloads;
}

// Bytes the sparse job must move: read the neutral, write the output, and
// per active entry read its index and delta and update one output vertex.
std::size_t ActiveEntries(const facerig::Rig& rig, const std::vector<float>& weights) {
  std::size_t entries = 0;
  for (std::size_t s = 0; s < weights.size(); ++s) {
    if (weights[s] != 0.0f) entries += rig.shape(s).vertex_indices.size();
  }
  return entries;
}

// The roofline kernel: stream exactly the sparse job's bytes, sequentially,
// with no index arithmetic: copy neutral -> output, read every (index, delta),
// read-modify-write one output-sized float3 per entry.
struct Roofline {
  std::vector<glm::vec3> neutral, output;
  std::vector<std::uint32_t> indices;
  std::vector<glm::vec3> deltas, updated;
  std::uint32_t sink = 0;

  Roofline(std::size_t vertices, std::size_t entries)
      : neutral(vertices, glm::vec3(1.0f)), output(vertices), indices(entries, 1u),
        deltas(entries, glm::vec3(0.5f)), updated(entries, glm::vec3(0.0f)) {}

  void Run() {
    std::memcpy(output.data(), neutral.data(), neutral.size() * sizeof(glm::vec3));
    std::uint32_t acc = 0;
    for (std::size_t i = 0; i < indices.size(); ++i) {
      acc += indices[i];
      updated[i] += deltas[i];
    }
    sink += acc;
  }
};

// One workload's medians and the bytes it moves.
struct WorkloadTimes {
  std::size_t entries = 0;
  std::size_t allocations = 0;  // most heap allocations in one positions-only run
  double sparse_us = 0.0;
  double blend_normals_us = 0.0;
  double recompute_normals_us = 0.0;
  double dense_us = 0.0;
  double roofline_us = 0.0;
  double bytes = 0.0;
  double sparse_gbps = 0.0;
  double roofline_gbps = 0.0;
};

// The measured part: the sparse job in each normal mode, the dense
// reference and the roofline kernel on the same weights.
WorkloadTimes TimeWorkload(const facerig::Rig& rig, const facerig::DenseBlendShapes& dense, const Workload& workload,
                           std::vector<glm::vec3>& positions, std::vector<glm::vec3>& normals,
                           Eigen::VectorXf& dense_out) {
  facerig::BlendJob job;
  job.rig = &rig;
  job.weights = workload.weights;
  job.out_positions = positions;
  job.out_normals = normals;

  WorkloadTimes t;
  job.normal_mode = facerig::NormalMode::kNone;
  t.sparse_us = MedianMicroseconds([&] {
    facerig::test::AllocationCounter counter;
    if (job.Run() != facerig::BlendJobError::kNone) std::abort();
    t.allocations = std::max(t.allocations, counter.count());
  });
  job.normal_mode = facerig::NormalMode::kBlendDeltas;
  t.blend_normals_us = MedianMicroseconds([&] { (void)job.Run(); });
  job.normal_mode = facerig::NormalMode::kRecompute;
  t.recompute_normals_us = MedianMicroseconds([&] { (void)job.Run(); });
  t.dense_us = MedianMicroseconds([&] { facerig::DenseBlend(dense, workload.weights, dense_out); });

  t.entries = ActiveEntries(rig, workload.weights);
  Roofline roofline(rig.vertex_count(), t.entries);
  t.roofline_us = MedianMicroseconds([&] { roofline.Run(); });
  t.bytes = static_cast<double>(rig.vertex_count() * 24 + t.entries * (4 + 12 + 24));
  t.sparse_gbps = t.bytes / (t.sparse_us * 1e3);
  t.roofline_gbps = t.bytes / (t.roofline_us * 1e3);
  return t;
}

void PrintTableHeader() {
  std::printf("\n%-9s %8s %9s | %9s %8s | %9s %8s | %10s %10s | %9s %8s %6s\n", "workload", "entries",
              "sparse us", "GB/s", "x roof", "dense us", "x faster", "+blend n", "+recomp n",
              "roof us", "GB/s", "allocs");
}

void PrintTableRow(const Workload& workload, const WorkloadTimes& t) {
  std::printf("%-9s %8zu %9.1f | %9.2f %8.2f | %9.1f %8.1f | %10.1f %10.1f | %9.1f %8.2f %6zu\n",
              workload.name.c_str(), t.entries, t.sparse_us, t.sparse_gbps, t.sparse_us / t.roofline_us,
              t.dense_us, t.dense_us / t.sparse_us, t.blend_normals_us, t.recompute_normals_us, t.roofline_us,
              t.roofline_gbps, t.allocations);
}

nlohmann::json WorkloadJson(const Workload& workload, const WorkloadTimes& t) {
  return {{"name", workload.name},
          {"active_shapes",
           std::count_if(workload.weights.begin(), workload.weights.end(), [](float w) { return w != 0.0f; })},
          {"active_entries", t.entries},
          {"sparse_us", t.sparse_us},
          {"sparse_blend_normals_us", t.blend_normals_us},
          {"sparse_recompute_normals_us", t.recompute_normals_us},
          {"dense_us", t.dense_us},
          {"roofline_us", t.roofline_us},
          {"bytes", t.bytes},
          {"sparse_gbps", t.sparse_gbps},
          {"roofline_gbps", t.roofline_gbps},
          {"sparse_over_roofline", t.sparse_us / t.roofline_us},
          {"dense_over_sparse", t.dense_us / t.sparse_us},
          {"allocations", t.allocations}};
}

}  // namespace

int RunBlendBenchmark(int argc, char** argv) {
  std::string rig_path = FACERIG_DEFAULT_ICT_DIR;
  std::string json_path;
  CLI::App app("sparse blend job vs dense Eigen reference vs memory roofline", "facerig-bench blend");
  app.add_option("--rig", rig_path, "the rig (default: the ICT-FaceKit folder)");
  app.add_option("--json", json_path, "write the results as JSON");
  if (const std::optional<int> exit_code = facerig::cli::ParseCommandLine(app, argc - 1, argv + 1)) return *exit_code;

  facerig::TemplateImportOptions options;
  options.with_normal_deltas = true;  // so both normal modes can be measured
  facerig::Rig rig;
  try {
    rig = facerig::LoadRigOrTemplateFolder(rig_path, options);
  } catch (const facerig::IoError& error) {
    return ReportBenchFailure(error);
  }
  std::printf("rig %s: %zu vertices, %zu triangles, %zu shapes, %zu sparse entries\n",
              rig_path.c_str(), rig.vertex_count(), rig.triangle_count(), rig.shape_count(),
              rig.total_shape_entries());

  const facerig::DenseBlendShapes dense = facerig::MakeDenseBlendShapes(rig);
  Eigen::VectorXf dense_out(dense.neutral.size());
  std::vector<glm::vec3> positions(rig.vertex_count()), normals(rig.vertex_count());

  nlohmann::json report;
  report["rig"] = rig_path;
  report["vertices"] = rig.vertex_count();
  report["shapes"] = rig.shape_count();
  PrintTableHeader();
  for (const Workload& workload : MakeWorkloads(rig)) {
    const WorkloadTimes times = TimeWorkload(rig, dense, workload, positions, normals, dense_out);
    PrintTableRow(workload, times);
    report["workloads"].push_back(WorkloadJson(workload, times));
  }
  std::printf("\nsparse us: positions only; +blend n / +recomp n: the same job with normals from\n"
              "blended normal deltas / recomputed from positions. roof: streaming the same bytes.\n");
  return WriteBenchJson(json_path, report);
}
