// `facerig landmarks` and `facerig register`, run in-process: outputs on a
// re-meshed ICT face (landmark JSON near the truth, debug PNG, fitted OBJ on
// the template's vertices in the target's coordinates, JSON reports), usage
// errors (exit code 2), and bad input (exit code 1, a message naming the
// problem, no output file).
#include "cli/app.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/registration/nonrigid_icp.h"
#include "facerig/runtime/io/obj.h"
#include "support/command_runner.h"
#include "support/ict_faces.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

test::CommandOutcome Landmarks(const std::vector<std::string>& arguments) {
  std::vector<std::string> all{"landmarks"};
  all.insert(all.end(), arguments.begin(), arguments.end());
  return test::RunCommand(cli::RunFacerig, all);
}

test::CommandOutcome Register(const std::vector<std::string>& arguments) {
  std::vector<std::string> all{"register"};
  all.insert(all.end(), arguments.begin(), arguments.end());
  return test::RunCommand(cli::RunFacerig, all);
}

using test::Contains;

// Nothing at `path`, not even the temporary file of an atomic write.
bool NothingWritten(const fs::path& path) {
  return !fs::exists(path) && !fs::exists(path.string() + ".tmp");
}

// A UV sphere (a closed mesh with no face on it).
void WriteSphere(const fs::path& path) {
  std::vector<glm::vec3> positions;
  std::vector<Triangle> triangles;
  test::MakeUvSphere(
      24, 32,
      [](double theta, double phi) {
        return glm::vec3(static_cast<float>(10.0 * std::sin(theta) * std::cos(phi)),
                         static_cast<float>(10.0 * std::cos(theta)),
                         static_cast<float>(10.0 * std::sin(theta) * std::sin(phi)));
      },
      positions, triangles);
  WriteObj(path, positions, {}, {}, triangles, {});
}

fs::path DefaultHead() { return FACERIG_DEFAULT_HEAD; }

// The ICT template folder: imported once (test::IctRig), then read by the
// command from the tests' template cache (catch_main.cpp) in ~0.1 s.
fs::path IctTemplate() {
  (void)test::IctRig();
  return test::IctDir();
}

// Re-meshed random ICT face (44,786 vertices), written as OBJ.
const test::RegistrationTarget& WriteTarget(const fs::path& path, std::uint32_t seed, double units_per_cm) {
  static test::RegistrationTarget target;
  test::RegistrationTargetOptions options;
  options.seed = seed;
  options.units_per_cm = units_per_cm;
  target = test::MakeRegistrationTarget(options);
  WriteObj(path, target.positions, {}, {}, target.triangles, {});
  return target;
}

// Mean distance of the fitted face region to the true ICT vertices, centimetres.
double FaceErrorCm(const std::vector<glm::vec3>& fitted, const test::RegistrationTarget& target) {
  double sum = 0.0;
  const std::uint32_t face = test::IctFaces().face_vertex_count();
  for (std::uint32_t v = 0; v < face; ++v) {
    sum += static_cast<double>(glm::length(fitted[v] - target.true_ict_positions[v]));
  }
  return sum / face / target.units_per_cm;
}

// The fitted OBJ has the template's vertices, its face region within
// `max_error_cm` of the target's true positions.
void CheckFittedFace(const fs::path& fitted, const test::RegistrationTarget& target, double max_error_cm) {
  const Mesh obj = ReadObj(fitted);
  REQUIRE(obj.positions.size() == test::IctRig().vertex_count());
  const double error_cm = FaceErrorCm(obj.positions, target);
  INFO("face region error " << error_cm << " cm");
  CHECK(error_cm < max_error_cm);
}

// The command failed (exit code 1), saying each of `messages`, and wrote
// none of `outputs`.
void CheckFailed(const test::CommandOutcome& outcome, std::initializer_list<const char*> messages,
                 std::initializer_list<fs::path> outputs) {
  INFO(outcome.error_output);
  CHECK(outcome.exit_code == 1);
  for (const char* message : messages) CHECK(Contains(outcome.error_output, message));
  for (const fs::path& output : outputs) CHECK(NothingWritten(output));
}

nlohmann::json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

}  // namespace

TEST_CASE("facerig landmarks / register: usage errors return 2", "[cli][landmarks]") {
  CHECK(Landmarks({}).exit_code == 2);
  CHECK(Landmarks({"mesh.obj"}).exit_code == 2);  // no -o
  CHECK(Landmarks({"mesh.obj", "-o"}).exit_code == 2);  // -o without a value
  const test::CommandOutcome unknown = Landmarks({"mesh.obj", "-o", "lm.json", "--frobnicate"});
  CHECK(unknown.exit_code == 2);
  CHECK(Contains(unknown.error_output, "facerig landmarks: The following argument was not expected: --frobnicate"));
  CHECK(Landmarks({"a.obj", "b.obj", "-o", "lm.json"}).exit_code == 2);  // two meshes

  CHECK(Register({}).exit_code == 2);
  CHECK(Register({"--template", "t.frig", "--target", "m.obj"}).exit_code == 2);  // no -o
  CHECK(Register({"--target", "m.obj", "-o", "f.obj"}).exit_code == 2);  // no template
  const test::CommandOutcome stray = Register({"--template", "t.frig", "--target", "m.obj", "-o", "f.obj", "extra"});
  CHECK(stray.exit_code == 2);
  CHECK(Contains(stray.error_output, "facerig register: The following argument was not expected: extra"));
}

TEST_CASE("facerig landmarks / register: bad input fails with a clear message and writes nothing",
          "[cli][landmarks]") {
  const fs::path folder = test::FreshOutputFolder("cli_register_bad");
  const fs::path out = folder / "lm.json", png = folder / "lm.png", fitted = folder / "fitted.obj";

  SECTION("missing file") {
    const test::CommandOutcome result = Landmarks({(folder / "missing.obj").string(), "-o", out.string()});
    CheckFailed(result, {"missing.obj"}, {out});
    const test::CommandOutcome fit = Register({"--template", DefaultHead().string(), "--target",
                                               (folder / "missing.obj").string(), "-o", fitted.string()});
    CheckFailed(fit, {"missing.obj"}, {fitted});
  }
  SECTION("NaN coordinates") {
    const fs::path mesh = folder / "nan.obj";
    std::ofstream(mesh) << "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n";
    const test::CommandOutcome result = Landmarks({mesh.string(), "-o", out.string(), "--debug-png", png.string()});
    CheckFailed(result, {"nan.obj", "non-finite"}, {out, png});
  }
  SECTION("empty mesh") {
    const fs::path mesh = folder / "empty.obj";
    std::ofstream(mesh) << "# vertices but no faces\nv 0 0 0\nv 1 0 0\n";
    const test::CommandOutcome result = Landmarks({mesh.string(), "-o", out.string()});
    CheckFailed(result, {"empty.obj", "no faces"}, {out});
  }
  SECTION("a mesh with no face suggests a landmark file") {
    const fs::path sphere = folder / "sphere.obj";
    WriteSphere(sphere);
    const test::CommandOutcome result = Landmarks({sphere.string(), "-o", out.string(), "--debug-png", png.string()});
    CheckFailed(result, {"no face", "--landmarks"}, {out, png});
    // register detects landmarks on the target first: the same advice, no OBJ.
    const test::CommandOutcome fit =
        Register({"--template", DefaultHead().string(), "--target", sphere.string(), "-o", fitted.string()});
    CheckFailed(fit, {"--landmarks"}, {fitted});
  }
  SECTION("a malformed landmark file") {
    const fs::path sphere = folder / "sphere.obj";
    WriteSphere(sphere);
    const fs::path landmarks = folder / "bad_landmarks.json";
    std::ofstream(landmarks) << R"({"points": [[0, 1, 2], [1, 2]]})";
    const test::CommandOutcome fit = Register({"--template", DefaultHead().string(), "--target", sphere.string(),
                                               "--landmarks", landmarks.string(), "-o", fitted.string()});
    CheckFailed(fit, {"bad_landmarks.json"}, {fitted});
  }
}

TEST_CASE("facerig landmarks on a re-meshed ICT face: 68 points near the truth, debug PNG, report (shared data)",
          "[cli][landmarks][shared-data]") {
  const fs::path folder = test::FreshOutputFolder("cli_landmarks");
  const fs::path mesh = folder / "target.obj", out = folder / "lm.json", png = folder / "lm.png",
                 report = folder / "report.json";
  const test::RegistrationTarget& target = WriteTarget(mesh, 41, 10.0);  // millimetres
  const test::CommandOutcome result =
      Landmarks({mesh.string(), "-o", out.string(), "--debug-png", png.string(), "--json", report.string()});
  INFO(result.error_output);
  REQUIRE(result.exit_code == 0);

  const FaceLandmarks landmarks = ReadLandmarksJson(out);
  REQUIRE(landmarks.points.size() == kDlibLandmarkCount);
  const double interocular = static_cast<double>(glm::length(target.true_landmarks[36] - target.true_landmarks[45]));
  double error = 0.0;
  for (std::size_t k = 17; k < kDlibLandmarkCount; ++k) {
    error += static_cast<double>(glm::length(landmarks.points[k] - target.true_landmarks[k])) / interocular / 51.0;
  }
  INFO("mean error without the jaw: " << error << " of the inter-ocular distance");
  CHECK(error < 0.04);  // one face: a little above the issue's 0.03 mean over faces
  CHECK(landmarks.confidence[0] < landmarks.confidence[30]);  // jaw points count less
  CHECK(fs::file_size(png) > 1000);

  const nlohmann::json json = ReadJson(report);
  CHECK(json["result"]["vertices"].get<std::size_t>() == target.positions.size());
  CHECK(json["timings"]["detect"].get<double>() > 0.0);
  CHECK(json["timings"]["load_model"].get<double>() > 0.0);
  CHECK(json["result"]["views_tried"].get<int>() >= 2);
  // Lid points on the eye, not the skin: listed, and left out of the file (confidence 0).
  REQUIRE(json["result"]["doubtful_lid_points"].is_array());
  for (const nlohmann::json& k : json["result"]["doubtful_lid_points"]) {
    CHECK(landmarks.confidence.at(k.get<std::size_t>()) == 0.0f);
  }
}

TEST_CASE("facerig register with a landmark file and --template-info: the template's vertices on the target, in its "
          "units (shared data)",
          "[cli][shared-data]") {
  const fs::path folder = test::FreshOutputFolder("cli_register_file");
  const fs::path mesh = folder / "target.obj", landmarks = folder / "lm.json", fitted = folder / "fitted.obj",
                 report = folder / "report.json";
  const test::RegistrationTarget& target = WriteTarget(mesh, 42, 0.01);  // metres
  FaceLandmarks truth;
  for (std::uint32_t k = 0; k < kDlibLandmarkCount; ++k) {
    truth.points.push_back(target.true_landmarks[k]);
    truth.confidence.push_back(k < 17 ? 0.3f : 1.0f);
    truth.indices.push_back(k);
  }
  WriteLandmarksJson(landmarks, truth);
  const fs::path descriptor = fs::path(FACERIG_SOURCE_DIR) / "data/templates/ict-facekit.template.json";
  const test::CommandOutcome result =
      Register({"--template", IctTemplate().string(), "--template-info", descriptor.string(), "--target",
                mesh.string(), "--landmarks", landmarks.string(), "-o", fitted.string(), "--json", report.string()});
  INFO(result.error_output);
  REQUIRE(result.exit_code == 0);
  CHECK(Contains(result.error_output, "non-rigid ICP"));  // the progress bar

  CheckFittedFace(fitted, target, 0.25);

  const nlohmann::json report_json = ReadJson(report);
  const nlohmann::json& json = report_json["result"];
  CHECK(json["landmarks"] == landmarks.string());
  CHECK(json["template_info"]["source"] == "explicit");  // --template-info, not the fingerprint match
  CHECK(json["template_info"]["path"] == descriptor.string());
  CHECK(json["residual_percent_of_diagonal"]["mean"].get<double>() < 0.1);
  CHECK(json["residual_percent_of_diagonal"]["p95"].get<double>() < 0.5);
  CHECK(json["rigid_scale"].get<double>() == Approx(0.01).epsilon(0.05));  // cm template onto metres
  const nlohmann::json& timings = report_json["timings"];
  for (const char* step : {"load", "landmarks", "rigid", "factorize", "nonrigid_total", "total"}) {
    CHECK(timings[step].get<double>() >= 0.0);
  }
  CHECK(timings["total"].get<double>() >= timings["nonrigid_total"].get<double>());
}

TEST_CASE("facerig register without landmarks detects them on the target (shared data)", "[cli][shared-data]") {
  const fs::path folder = test::FreshOutputFolder("cli_register_detect");
  const fs::path mesh = folder / "target.obj", fitted = folder / "fitted.obj", report = folder / "report.json";
  const test::RegistrationTarget& target = WriteTarget(mesh, 43, 1.0);
  const test::CommandOutcome result = Register({"--template", IctTemplate().string(), "--target", mesh.string(), "-o",
                                                fitted.string(), "--json", report.string()});
  INFO(result.error_output);
  REQUIRE(result.exit_code == 0);
  CHECK(Contains(result.error_output, "detecting landmarks on the target"));

  CheckFittedFace(fitted, target, 0.3);
  const nlohmann::json json = ReadJson(report);
  CHECK(json["result"]["landmarks"] == "detected");
  CHECK(json["timings"]["landmarks"].get<double>() > 0.0);
}

}  // namespace facerig
