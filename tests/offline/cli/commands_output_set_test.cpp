// `facerig landmarks`, `register`, `average`, `caricature` and `morph` write
// their outputs as one set (output_set.h): a write that fails (the last one,
// the report, or an earlier one), a failed rename or SIGTERM between writes
// leaves the previous outputs byte for byte and no temporaries; a kill leaves
// them too, and the next run removes its temporaries; a run replaces every
// output, with the files an OBJ brings beside it.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "cli/app.h"
#include "facerig/offline/default_head/default_head.h"
#include "facerig/offline/rigging/face_template.h"
#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/runtime/io/mtl.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/runtime/rig_builder.h"
#include "command_report_check.h"
#include "output_set_files.h"
#include "support/command_runner.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

// One command with every output asked for, writing into `out`.
struct CommandCase {
  std::string name;
  std::vector<std::string> arguments;
  std::vector<std::string> outputs;  // file names in `out`, sorted
};

// Two small grid rigs of one topology, made once.
struct Inputs {
  fs::path grid_a, grid_b;
};

const Inputs& MakeInputs() {
  static const Inputs inputs = [] {
    const fs::path folder = test::FreshOutputFolder("commands_set_inputs");
    Inputs made{folder / "a.frig", folder / "b.frig"};
    for (const auto& [path, bend] : {std::pair{made.grid_a, 0.3f}, std::pair{made.grid_b, -0.2f}}) {
      RawRig raw = test::MakeGridRawRig(6, 2);
      for (glm::vec3& p : raw.positions) p.z += bend * p.x * p.y;
      SaveRig(path, *RigBuilder::Build(std::move(raw)));
    }
    return made;
  }();
  return inputs;
}

// The built-in head's descriptor with its landmark vertices (detected once,
// as the descriptor derives them), and those vertices as landmarks of the
// head itself: register then detects nothing.
struct HeadFiles {
  fs::path descriptor, landmarks;
};

HeadFiles WriteHeadFiles() {
  const fs::path folder = test::FreshOutputFolder("commands_set_head");
  const HeadFiles files{folder / "head.template.json", folder / "head_landmarks.json"};
  const Rig head = LoadRig(FACERIG_DEFAULT_HEAD);
  FaceTemplateInfo info = DefaultHeadTemplateInfo(head);
  LandmarkDetector detector{LandmarkParams{}};
  (void)TemplateLandmarkVertices(head, info, detector);
  test::WriteText(files.descriptor, FaceTemplateInfoToJson(info));
  const std::optional<FaceLandmarks> landmarks =
      LandmarksOnTemplateTopology(head, info, head.positions(), head.triangles());
  REQUIRE(landmarks.has_value());
  WriteLandmarksJson(files.landmarks, *landmarks);
  return files;
}

CommandCase Landmarks(const fs::path& out) {
  return {"landmarks",
          {"landmarks", FACERIG_DEFAULT_HEAD, "-o", (out / "landmarks.json").string(), "--debug-png",
           (out / "landmarks.png").string(), "--json", (out / "report.json").string()},
          {"landmarks.json", "landmarks.png", "report.json"}};
}

CommandCase Register(const fs::path& out) {
  const HeadFiles head = WriteHeadFiles();
  return {"register",
          {"register", "--template", FACERIG_DEFAULT_HEAD, "--template-info", head.descriptor.string(), "--target",
           FACERIG_DEFAULT_HEAD, "--landmarks", head.landmarks.string(), "-o", (out / "fitted.obj").string(),
           "--json", (out / "report.json").string()},
          {"fitted.obj", "report.json"}};
}

std::vector<CommandCase> IdentityCommands(const std::string& folder_name) {
  const Inputs& in = MakeInputs();
  const auto out = [&folder_name](const std::string& command) {
    return test::FreshOutputFolder(folder_name + "_" + command);
  };
  const fs::path average = out("average"), caricature = out("caricature"), morph = out("morph");
  return {{"average",
           {"average", in.grid_a.string(), in.grid_b.string(), "-o", (average / "average.obj").string(), "--json",
            (average / "report.json").string()},
           {"average.obj", "report.json"}},
          {"caricature",
           {"caricature", "--rig", in.grid_a.string(), "--average", in.grid_b.string(), "--factor", "0.5", "-o",
            (caricature / "caricature.glb").string(), "--json", (caricature / "report.json").string()},
           {"caricature.glb", "report.json"}},
          {"morph",
           {"morph", "--template", in.grid_a.string(), "--target", in.grid_b.string(), "-o",
            (morph / "morph.frig").string(), "--json", (morph / "report.json").string()},
           {"morph.frig", "report.json"}}};
}

// The folder of a case's outputs.
fs::path OutputFolder(const CommandCase& command) {
  for (std::size_t i = 0; i + 1 < command.arguments.size(); ++i) {
    if (command.arguments[i] == "-o") return fs::path(command.arguments[i + 1]).parent_path();
  }
  FAIL("no -o in " << command.name);
  return {};
}

void WritePreviousOutputs(const CommandCase& command) {
  for (const std::string& name : command.outputs) test::WriteText(OutputFolder(command) / name, "old " + name);
}

// The folder holds the previous outputs, unchanged, and nothing else.
void CheckPreviousOutputsIntact(const CommandCase& command) {
  const fs::path out = OutputFolder(command);
  CHECK(test::Names(out) == command.outputs);
  for (const std::string& name : command.outputs) CHECK(test::ReadText(out / name) == "old " + name);
}

// Runs the command in-process with FACERIG_INJECT_FAILURE=`failure` (none when empty).
test::CommandOutcome RunWithFailure(const CommandCase& command, const std::string& failure) {
  if (failure.empty()) {
    unsetenv("FACERIG_INJECT_FAILURE");
  } else {
    setenv("FACERIG_INJECT_FAILURE", failure.c_str(), 1);
  }
  const test::CommandOutcome outcome = test::RunCommand(cli::RunFacerig, command.arguments);
  unsetenv("FACERIG_INJECT_FAILURE");
  return outcome;
}

// A failed write of `failed_output` (the step `failure`): exit code 1, an
// error naming the final path, the previous outputs kept.
void CheckFailedWrite(const CommandCase& command, const std::string& failure, const std::string& failed_output) {
  WritePreviousOutputs(command);
  const test::CommandOutcome outcome = RunWithFailure(command, failure);
  INFO(command.name << " with " << failure << ": " << outcome.error_output);
  CHECK(outcome.exit_code == 1);
  const std::string message = "cannot write " + (OutputFolder(command) / failed_output).string() +
                              ": No space left on device; the previous outputs are unchanged";
  CHECK(outcome.error_output.find(message) != std::string::npos);
  CheckPreviousOutputsIntact(command);
}

// A normal run: every output replaced, no temporaries; the report names the output.
void CheckReplaced(const CommandCase& command) {
  WritePreviousOutputs(command);
  const test::CommandOutcome outcome = RunWithFailure(command, "");
  INFO(command.name << ": " << outcome.error_output);
  REQUIRE(outcome.exit_code == 0);
  const fs::path out = OutputFolder(command);
  CHECK(test::Names(out) == command.outputs);
  for (const std::string& name : command.outputs) CHECK(test::ReadText(out / name).rfind("old ", 0) != 0);
  const nlohmann::json report = nlohmann::json::parse(test::ReadText(out / "report.json"));
  test::CheckCommandReport(report, command.name);
  CHECK(report["outputs"][0]["path"] == (out / command.outputs[0]).string());
}

// `average` of the textured built-in head with itself, as an OBJ.
CommandCase TexturedAverage(const fs::path& out) {
  const std::string head = FACERIG_DEFAULT_HEAD;
  return {"average",
          {"average", head, head, "-o", (out / "average.obj").string(), "--json", (out / "report.json").string()},
          {"average.obj", "report.json"}};
}

// A normal run writes the OBJ, its MTL under the OBJ's final name (it loads
// through the mtllib line) and the images, and leaves no temporaries.
void CheckTexturedAverage(const CommandCase& command) {
  const test::CommandOutcome outcome = RunWithFailure(command, "");
  INFO(outcome.error_output);
  REQUIRE(outcome.exit_code == 0);
  const fs::path out = OutputFolder(command);
  const Rig written = LoadRig(out / "average.obj");
  const Rig original = LoadRig(FACERIG_DEFAULT_HEAD);
  CHECK(written.materials().size() == original.materials().size());
  CHECK(written.images().size() == original.images().size());
  std::vector<std::string> expected{"average.mtl", "average.obj", "report.json"};
  for (const std::string& name : ImageFileNames(original.images())) expected.push_back(name);
  std::sort(expected.begin(), expected.end());
  CHECK(test::Names(out) == expected);
}

}  // namespace

TEST_CASE("facerig average / caricature / morph: a failed write or rename, or SIGTERM, keeps the previous outputs",
          "[cli][output-set]") {
  for (const CommandCase& command : IdentityCommands("identity_failed")) {
    CheckFailedWrite(command, "fail-report", "report.json");
    CheckFailedWrite(command, "fail-rig", command.outputs[0]);

    WritePreviousOutputs(command);
    const test::CommandOutcome renamed = RunWithFailure(command, "rename");
    CHECK(renamed.exit_code == 1);
    CHECK(renamed.error_output.find("the previous outputs are unchanged") != std::string::npos);
    CheckPreviousOutputsIntact(command);

    const test::CommandOutcome stopped = RunWithFailure(command, "term-after-rig");
    INFO(stopped.error_output);
    CHECK(stopped.exit_code == 128 + SIGTERM);
    CHECK(stopped.error_output.find("interrupted by SIGTERM; nothing written, the previous outputs are unchanged") !=
          std::string::npos);
    CheckPreviousOutputsIntact(command);
  }
}

TEST_CASE("facerig average / caricature / morph: a run replaces the output and its report", "[cli][output-set]") {
  for (const CommandCase& command : IdentityCommands("identity_replaced")) {
    CheckReplaced(command);
    const fs::path output = OutputFolder(command) / command.outputs[0];
    // Each temporary kept its extension, so the writer chose the format asked for (OBJ, GLB, .frig).
    const Rig written = LoadRig(output);
    CHECK(written.vertex_count() == LoadRig(MakeInputs().grid_a).vertex_count());
    const std::size_t input_shapes = LoadRig(MakeInputs().grid_b).shape_count();
    CHECK(written.shape_count() == (command.name == "average" ? 0 : input_shapes + (command.name == "morph")));
  }
}

TEST_CASE("facerig average -o X.obj of textured heads: the OBJ, its MTL and images are outputs of the set",
          "[cli][output-set]") {
  const CommandCase command = TexturedAverage(test::FreshOutputFolder("average_textured_set"));
  CheckFailedWrite(command, "fail-report", "report.json");  // no MTL or image left beside the old OBJ
  CheckTexturedAverage(command);
}

TEST_CASE("facerig average killed between its writes: the previous outputs stay, the next run removes the "
          "temporaries",
          "[cli][output-set]") {
  const CommandCase command = TexturedAverage(test::FreshOutputFolder("average_killed_set"));
  WritePreviousOutputs(command);
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    RunWithFailure(command, "kill-after-rig");
    _exit(0);  // not reached: the run kills itself
  }
  int status = 0;
  REQUIRE(waitpid(child, &status, 0) == child);
  CHECK((WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL));
  const fs::path out = OutputFolder(command);
  CHECK(!test::Temporaries(out).empty());  // no chance to clean up
  for (const std::string& name : command.outputs) CHECK(test::ReadText(out / name) == "old " + name);
  CheckTexturedAverage(command);
}

TEST_CASE("facerig landmarks on the built-in head: a failed write keeps the previous JSON, PNG and report",
          "[cli][output-set]") {
  const CommandCase command = Landmarks(test::FreshOutputFolder("landmarks_set"));
  CheckFailedWrite(command, "fail-report", "report.json");
  CheckFailedWrite(command, "fail-debug-png", "landmarks.png");

  CheckReplaced(command);
  const fs::path out = OutputFolder(command);
  CHECK(ReadLandmarksJson(out / "landmarks.json").points.size() == kDlibLandmarkCount);
  // Written under a temporary name that kept ".png": a PNG, not another format.
  CHECK(test::ReadText(out / "landmarks.png").rfind("\x89PNG\r\n\x1a\n", 0) == 0);
  CHECK(nlohmann::json::parse(test::ReadText(out / "report.json"))["result"]["views_tried"].get<int>() >= 1);
}

TEST_CASE("facerig register of the built-in head onto itself: a failed write keeps the previous OBJ and report",
          "[cli][output-set]") {
  const CommandCase command = Register(test::FreshOutputFolder("register_set"));
  CheckFailedWrite(command, "fail-report", "report.json");

  CheckReplaced(command);
  const Rig head = LoadRig(FACERIG_DEFAULT_HEAD);
  CHECK(ReadObj(OutputFolder(command) / "fitted.obj").positions.size() == head.vertex_count());
}

TEST_CASE("facerig convert to X.obj: the OBJ, its MTL and images arrive as one set, or nothing does",
          "[cli][output-set]") {
  const fs::path out = test::FreshOutputFolder("convert_textured_set");
  const CommandCase command{
      "convert", {"convert", FACERIG_DEFAULT_HEAD, (out / "head.obj").string(), "--neutral-only"}, {"head.obj"}};
  const test::CommandOutcome failed = RunWithFailure(command, "fail-rig");
  CHECK(failed.exit_code == 1);
  CHECK(test::Names(out).empty());  // no MTL or image left without its OBJ, no temporaries

  const test::CommandOutcome outcome = RunWithFailure(command, "");
  INFO(outcome.error_output);
  REQUIRE(outcome.exit_code == 0);
  const Rig original = LoadRig(FACERIG_DEFAULT_HEAD);
  std::vector<std::string> expected{"head.mtl", "head.obj"};
  for (const std::string& name : ImageFileNames(original.images())) expected.push_back(name);
  std::sort(expected.begin(), expected.end());
  CHECK(test::Names(out) == expected);
  CHECK(LoadRig(out / "head.obj").images().size() == original.images().size());
}

}  // namespace facerig
