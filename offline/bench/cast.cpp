#include "bench/cast.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/common.h"
#include "bench/json.h"
#include "cli/app.h"
#include "facerig/runtime/io/obj.h"
#include "measure/registration_targets.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using facerig::SecondsSince;

struct CastOptions {
  std::string ict_dir = FACERIG_DEFAULT_ICT_DIR;
  std::string json_path;
  std::string work_dir;  // empty: a temporary folder, removed
  int faces = 6;
  unsigned seed = 601;  // the build bench's faces
  std::size_t target_vertices = 30000;
};

void AddCastOptions(CLI::App& app, CastOptions& o) {
  app.add_option("--ict", o.ict_dir, "the ICT-FaceKit folder (the template)");
  app.add_option("--faces", o.faces, "random faces (default 6), plus one target without a face")
      ->check(facerig::cli::InRange(1, 1000));
  app.add_option("--seed", o.seed, "first random seed (default 601, as facerig-bench build)");
  app.add_option("--target-vertices", o.target_vertices, "vertices of each re-meshed face (default 30000)")
      ->check(facerig::cli::InRange(1000, 10000000));
  app.add_option("--json", o.json_path, "write the results as JSON");
  app.add_option("--work", o.work_dir, "keep the faces and the rigs in this folder (default: a temporary one)");
}

// The faces as OBJ files in `folder` (face_SEED.obj) and a flat sheet where
// no face is found (noface.obj); returns their names (file stems), sorted.
std::vector<std::string> WriteTargets(const CastOptions& o, const fs::path& folder) {
  const facerig::test::IctFaceModel model = facerig::test::LoadIctFaces(o.ict_dir);
  std::vector<std::string> names;
  for (int f = 0; f < o.faces; ++f) {
    facerig::test::RegistrationTargetOptions options;
    options.seed = o.seed + static_cast<unsigned>(f);
    options.target_vertex_count = o.target_vertices;
    options.units_per_cm = kUnitCycle[f % 3];
    const facerig::test::RegistrationTarget target = facerig::test::MakeRegistrationTarget(model, options);
    names.push_back("face_" + std::to_string(options.seed));
    facerig::WriteObj(folder / (names.back() + ".obj"), target.positions, {}, {}, target.triangles, {});
  }
  // A 30 x 30 grid: a mesh, but no view of it shows a face.
  std::vector<glm::vec3> sheet;
  std::vector<facerig::Triangle> triangles;
  constexpr std::uint32_t kSide = 30;
  for (std::uint32_t y = 0; y < kSide; ++y) {
    for (std::uint32_t x = 0; x < kSide; ++x) sheet.emplace_back(static_cast<float>(x), static_cast<float>(y), 0.0f);
  }
  for (std::uint32_t y = 0; y + 1 < kSide; ++y) {
    for (std::uint32_t x = 0; x + 1 < kSide; ++x) {
      const std::uint32_t v = y * kSide + x;
      triangles.push_back({v, v + 1, v + kSide});
      triangles.push_back({v + 1, v + kSide + 1, v + kSide});
    }
  }
  facerig::WriteObj(folder / "noface.obj", sheet, {}, {}, triangles, {});
  names.push_back("noface");
  return names;
}

// `facerig build ARGS...` in this process; its exit code.
int RunBuild(std::vector<std::string> arguments) {
  arguments.insert(arguments.begin(), {"facerig", "build"});
  std::vector<char*> argv;
  for (std::string& a : arguments) argv.push_back(a.data());
  return facerig::cli::RunFacerig(static_cast<int>(argv.size()), argv.data());
}

std::string FileBytes(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

// One face's two builds.
struct FaceTimes {
  std::string name;
  double single_seconds = 0.0;
  int single_exit = 0;
  double cast_seconds = 0.0;  // its share of the cast run (its report's time)
  std::string cast_status;
  bool identical = false;
};

int RunCast(const CastOptions& o) {
  try {
    const fs::path work = o.work_dir.empty() ? fs::temp_directory_path() / "facerig_bench_cast" : fs::path(o.work_dir);
    if (o.work_dir.empty()) {
      fs::remove_all(work);
    } else if (fs::exists(work) && !fs::is_empty(work)) {
      throw std::runtime_error("--work " + o.work_dir + " is not empty");
    }
    for (const char* sub : {"faces", "single", "cast"}) fs::create_directories(work / sub);
    std::printf("making %d random ICT faces of %zu vertices (seeds %u..) and a target without a face...\n", o.faces,
                o.target_vertices, o.seed);
    const std::vector<std::string> names = WriteTargets(o, work / "faces");

    std::vector<FaceTimes> faces;
    double single_total = 0.0;
    for (const std::string& name : names) {
      FaceTimes face;
      face.name = name;
      const auto start = Clock::now();
      face.single_exit = RunBuild({"--template", o.ict_dir, "--target", (work / "faces" / (name + ".obj")).string(),
                                   "-o", (work / "single" / (name + ".glb")).string()});
      face.single_seconds = SecondsSince(start);
      single_total += face.single_seconds;
      faces.push_back(face);
    }
    const auto cast_start = Clock::now();
    const int cast_exit = RunBuild({"--template", o.ict_dir, "--target", (work / "faces").string(), "--output-dir",
                                    (work / "cast").string(), "--json", (work / "summary.json").string()});
    const double cast_total = SecondsSince(cast_start);
    const nlohmann::json summary = nlohmann::json::parse(std::ifstream(work / "summary.json"));
    const nlohmann::json& timings = summary["timings"];
    for (FaceTimes& face : faces) {
      for (const nlohmann::json& target : summary["result"]["targets"]) {
        if (target["name"] != face.name) continue;
        face.cast_seconds = target["seconds"].get<double>();
        face.cast_status = target["status"].get<std::string>();
      }
      const fs::path single = work / "single" / (face.name + ".glb");
      face.identical = fs::exists(single) && FileBytes(single) == FileBytes(work / "cast" / (face.name + ".glb"));
    }

    std::printf("\n%zu targets (%d faces + noface.obj), template %s; wall seconds:\n", names.size(), o.faces,
                o.ict_dir.c_str());
    std::printf("  %-12s %14s %14s  %-10s %s\n", "target", "single build", "in the cast", "cast", "rig identical");
    int built = 0;
    double built_single = 0.0, built_cast = 0.0;
    nlohmann::json per_face = nlohmann::json::array();
    for (const FaceTimes& face : faces) {
      const bool ok = face.cast_status == "built";
      std::printf("  %-12s %14.2f %14.2f  %-10s %s\n", face.name.c_str(), face.single_seconds, face.cast_seconds,
                  face.cast_status.c_str(), ok ? (face.identical ? "yes" : "NO") : "-");
      if (ok) {
        ++built;
        built_single += face.single_seconds;
        built_cast += face.cast_seconds;
      }
      per_face.push_back({{"name", face.name}, {"single_seconds", face.single_seconds},
                          {"single_exit_code", face.single_exit}, {"cast_seconds", face.cast_seconds},
                          {"cast_status", face.cast_status}, {"identical", face.identical}});
    }
    const double template_once = timings["load_template"].get<double>() + timings["prepare_template"].get<double>();
    std::printf("  template in the cast, once: load %.2f s, prepare %.2f s\n", timings["load_template"].get<double>(),
                timings["prepare_template"].get<double>());
    std::printf("  whole run: %zu single builds %.2f s; one cast %.2f s (exit code %d, 3: some failed)\n",
                names.size(), single_total, cast_total, cast_exit);
    std::printf("  per built face: single %.2f s, in the cast %.2f s (%.2f s with the template's share), %.2fx\n",
                built_single / built, built_cast / built, cast_total / built, single_total / cast_total);
    const nlohmann::json report = {
        {"benchmark", "cast"}, {"faces", o.faces}, {"seed", o.seed}, {"target_vertices", o.target_vertices},
        {"template", o.ict_dir}, {"targets", per_face}, {"single_total_seconds", single_total},
        {"cast_total_seconds", cast_total}, {"cast_exit_code", cast_exit}, {"template_once_seconds", template_once},
        {"built", built}, {"single_seconds_per_built_face", built_single / built},
        {"cast_seconds_per_built_face", built_cast / built}};
    if (o.work_dir.empty()) fs::remove_all(work);
    return WriteBenchJson(o.json_path, report);
  } catch (const std::exception& error) {
    return ReportBenchFailure(error);
  }
}

}  // namespace

int RunCastBenchmark(int argc, char** argv) {
  return ParseAndRunBench<CastOptions>(argc, argv,
                                       "a cast of faces built in one facerig build run against one run per face",
                                       "facerig-bench cast", AddCastOptions, RunCast);
}
