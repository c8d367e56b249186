// `facerig build` and `facerig default-head` write their outputs as one set
// (output_set.h): a write that fails part-way, SIGTERM, or a kill between two
// writes leaves the previous complete set; a run replaces it whole (the
// --obj-dir folder replaced, not merged) and removes a killed run's
// temporaries.
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "cli/app.h"
#include "command_report_check.h"
#include "facerig/runtime/io/output_set.h"
#include "facerig/runtime/io/rig_file.h"
#include "support/command_runner.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void WriteText(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::vector<std::string> Names(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::string> Temporaries(const fs::path& folder) {
  std::vector<std::string> names;
  for (const std::string& name : Names(folder)) {
    if (name.rfind(kTemporaryPrefix, 0) == 0) names.push_back(name);
  }
  return names;
}

// A previous set with known contents: rig, .frig, report and an OBJ folder of two files.
fs::path MakePreviousSet(const std::string& name) {
  const fs::path out = test::FreshOutputFolder("build_set_" + name);
  fs::create_directories(out / "objs");
  WriteText(out / "face.glb", "old glb");
  WriteText(out / "face.frig", "old frig");
  WriteText(out / "report.json", "old report");
  WriteText(out / "objs" / "neutral.obj", "old neutral");
  WriteText(out / "objs" / "from_an_older_run.obj", "old shape");
  return out;
}

void CheckPreviousSetIntact(const fs::path& out) {
  CHECK(ReadText(out / "face.glb") == "old glb");
  CHECK(ReadText(out / "face.frig") == "old frig");
  CHECK(ReadText(out / "report.json") == "old report");
  CHECK(Names(out / "objs") == std::vector<std::string>{"from_an_older_run.obj", "neutral.obj"});
  CHECK(ReadText(out / "objs" / "neutral.obj") == "old neutral");
}

// The built-in head onto itself (about 6 s), every output asked for.
std::vector<std::string> BuildArguments(const fs::path& out) {
  const std::string head = FACERIG_DEFAULT_HEAD;
  return {"build", "--template", head, "--target", head, "-o", (out / "face.glb").string(), "--frig",
          (out / "face.frig").string(), "--obj-dir", (out / "objs").string(), "--json",
          (out / "report.json").string()};
}

// Runs the build in-process with FACERIG_INJECT_FAILURE=`failure`.
test::CommandOutcome BuildWithFailure(const fs::path& out, const std::string& failure) {
  if (failure.empty()) {
    unsetenv("FACERIG_INJECT_FAILURE");
  } else {
    setenv("FACERIG_INJECT_FAILURE", failure.c_str(), 1);
  }
  const test::CommandOutcome outcome = test::RunCommand(cli::RunFacerig, BuildArguments(out));
  unsetenv("FACERIG_INJECT_FAILURE");
  return outcome;
}

void CheckNewSet(const fs::path& out) {
  const Rig frig = LoadRig(out / "face.frig");
  CHECK(LoadRig(out / "face.glb").vertex_count() == frig.vertex_count());
  CHECK(nlohmann::json::parse(ReadText(out / "report.json"))["result"]["shapes"] == frig.shape_count());
  // Replaced, not merged: the older run's shape is gone.
  CHECK(!fs::exists(out / "objs" / "from_an_older_run.obj"));
  // neutral.obj, one OBJ per shape, and the head's materials.mtl with its skin and eye images.
  const std::vector<std::string> names = Names(out / "objs");
  CHECK(std::count_if(names.begin(), names.end(), [](const std::string& name) { return name.ends_with(".obj"); }) ==
        static_cast<std::ptrdiff_t>(frig.shape_count() + 1));
  CHECK(std::count(names.begin(), names.end(), "materials.mtl") == 1);
  CHECK(names.size() == frig.shape_count() + 1 + 1 + frig.images().size());
  CHECK(ReadText(out / "objs" / "neutral.obj").rfind("old", 0) != 0);
}

}  // namespace

TEST_CASE("facerig build: a failed write, a failed rename or SIGTERM at any point keeps the previous set",
          "[cli][output-set]") {
  struct Case {
    std::string failure;
    int exit_code;
    std::string message;
  };
  for (const Case& point : std::vector<Case>{
           {"fail-rig", 1, "/face.glb: No space left on device"},
           {"fail-obj-neutral", 1, "/objs/neutral.obj: No space left on device"},
           {"term-after-frig", 128 + SIGTERM, "interrupted by SIGTERM; nothing written"},
           {"term-after-obj-dir", 128 + SIGTERM, "interrupted by SIGTERM; nothing written"},
           {"rename", 1, "cannot rename .facerig-tmp-"}}) {
    const fs::path out = MakePreviousSet(point.failure);
    const test::CommandOutcome outcome = BuildWithFailure(out, point.failure);
    INFO(point.failure << ": " << outcome.error_output);
    CHECK(outcome.exit_code == point.exit_code);
    CHECK(outcome.error_output.find(point.message) != std::string::npos);
    CHECK(outcome.error_output.find("the previous outputs are unchanged") != std::string::npos);
    // Errors name the final paths (a failed rename names the temporary it could not move).
    CHECK((outcome.error_output.find(kTemporaryPrefix) == std::string::npos || point.failure == "rename"));
    CheckPreviousSetIntact(out);
    CHECK(Temporaries(out).empty());
  }
}

TEST_CASE("facerig build: killed between writes, the previous set stays, the next run cleans up and replaces it",
          "[cli][output-set]") {
  const fs::path out = MakePreviousSet("killed");
  for (const std::string failure : {"kill-after-rig", "kill-after-obj-dir"}) {
    std::string command = "FACERIG_INJECT_FAILURE=" + failure + " '" FACERIG_CLI_EXE "'";
    for (const std::string& argument : BuildArguments(out)) command += " '" + argument + "'";
    const int status = std::system((command + " >/dev/null 2>&1").c_str());
    INFO(failure);
    CHECK(((WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) ||
           (WIFEXITED(status) && WEXITSTATUS(status) == 128 + SIGKILL)));
    CheckPreviousSetIntact(out);
    CHECK(!Temporaries(out).empty());  // no chance to clean up
  }
  const test::CommandOutcome outcome = BuildWithFailure(out, "");
  INFO(outcome.error_output);
  REQUIRE(outcome.exit_code == 0);
  CheckNewSet(out);
  CHECK(Temporaries(out).empty());
  CHECK(Temporaries(out / "objs").empty());
}

TEST_CASE("facerig build: an --obj-dir holding other files is not replaced", "[cli][output-set]") {
  const fs::path out = MakePreviousSet("foreign");
  WriteText(out / "objs" / "notes.txt", "mine");
  const test::CommandOutcome outcome = BuildWithFailure(out, "");
  INFO(outcome.error_output);
  CHECK(outcome.exit_code == 1);
  CHECK(outcome.error_output.find("holds notes.txt, not only .obj, .mtl, .png and .jpg files") != std::string::npos);
  CHECK(ReadText(out / "objs" / "notes.txt") == "mine");
  CHECK(ReadText(out / "objs" / "neutral.obj") == "old neutral");
  CHECK(ReadText(out / "face.glb") == "old glb");
  CHECK(ReadText(out / "face.frig") == "old frig");
  CHECK(Temporaries(out).empty());
}

TEST_CASE("facerig default-head: its files are one set", "[cli][output-set]") {
  const fs::path out = test::FreshOutputFolder("default_head_set");
  for (const char* name : {"default_head.glb", "default_head.frig", "default_head.template.json"}) {
    WriteText(out / name, std::string("old ") + name);
  }
  setenv("FACERIG_INJECT_FAILURE", "fail-frig", 1);
  const test::CommandOutcome failed = test::RunCommand(cli::RunFacerig, {"default-head", out.string()});
  unsetenv("FACERIG_INJECT_FAILURE");
  INFO(failed.error_output);
  CHECK(failed.exit_code == 1);
  CHECK(failed.error_output.find("cannot write " + (out / "default_head.frig").string() +
                                 ": No space left on device; the previous outputs are unchanged") !=
        std::string::npos);
  for (const char* name : {"default_head.glb", "default_head.frig", "default_head.template.json"}) {
    CHECK(ReadText(out / name) == std::string("old ") + name);
  }
  CHECK(Temporaries(out).empty());

  const fs::path report = out / "report.json";
  const test::CommandOutcome done =
      test::RunCommand(cli::RunFacerig, {"default-head", out.string(), "--json", report.string()});
  REQUIRE(done.exit_code == 0);
  const nlohmann::json report_json = nlohmann::json::parse(ReadText(report));
  test::CheckCommandReport(report_json, "default-head");
  CHECK(report_json["outputs"].size() == 3);  // no --preview
  CHECK(report_json["outputs"][0]["path"] == (out / "default_head.glb").string());
  CHECK(report_json["result"]["shapes"] == LoadRig(out / "default_head.frig").shape_count());
  CHECK(LoadRig(out / "default_head.glb").vertex_count() == LoadRig(out / "default_head.frig").vertex_count());
  CHECK(ReadText(out / "default_head.template.json") == ReadText(fs::path(FACERIG_SOURCE_DIR) / "data" /
                                                                 "templates" / "default_head.template.json"));
  CHECK(Temporaries(out).empty());
}

}  // namespace facerig
