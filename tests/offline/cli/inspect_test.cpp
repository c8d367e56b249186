// `facerig inspect` and `convert`: a rig that cannot speak or blink is said so
// once on stderr, and in the --json report (rig_warnings.h); the reports have
// the schema of every command's (cli_report.h).
#include "cli/app.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "command_report_check.h"
#include "facerig/runtime/io/rig_file.h"
#include "support/command_runner.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;
using facerig::test::CountOccurrences;

}  // namespace

TEST_CASE("facerig inspect: warns once about a rig that cannot speak or blink, also in --json", "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_inspect_warnings");
  SaveRig(folder / "still.frig", test::MakeGridRig(4, 0));
  const test::CommandOutcome still = test::RunCommand(
      cli::RunFacerig, {"inspect", (folder / "still.frig").string(), "--json", (folder / "still.json").string()});
  INFO(still.error_output);
  REQUIRE(still.exit_code == 0);
  CHECK(CountOccurrences(still.error_output,
                         "facerig: warning: the rig cannot speak: it has no mouth, jaw or viseme shapes") == 1);
  CHECK(CountOccurrences(still.error_output, "facerig: warning: the rig cannot blink: it has no blink shapes") == 1);
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(folder / "still.json"));
  test::CheckCommandReport(report, "inspect");
  CHECK(report["inputs"] == nlohmann::json::array({{{"role", "rig"}, {"path", (folder / "still.frig").string()}}}));
  CHECK(report["outputs"].empty());
  REQUIRE(report["warnings"].size() == 2);
  CHECK(report["warnings"][0]["code"] == "cannot_speak");
  CHECK(report["warnings"][1]["code"] == "cannot_blink");
  CHECK(report["warnings"][1]["message"] == "the rig cannot blink: it has no blink shapes (eyeBlink_L, eyeBlink_R)");
  CHECK(report["result"]["vertices"] == 16);
  CHECK(report["result"]["shapes"].empty());

  // The built-in head speaks and blinks: no warning, an empty list.
  const test::CommandOutcome head = test::RunCommand(
      cli::RunFacerig, {"inspect", FACERIG_DEFAULT_HEAD, "--json", (folder / "head.json").string()});
  REQUIRE(head.exit_code == 0);
  CHECK(head.error_output.find("warning") == std::string::npos);
  const nlohmann::json head_report = nlohmann::json::parse(std::ifstream(folder / "head.json"));
  CHECK(head_report["warnings"].empty());
  CHECK(head_report["result"]["shapes"].size() > 10);
}

TEST_CASE("facerig convert --json: the report of the written rig, with its warnings, one of the set", "[cli][output-set]") {
  const fs::path folder = test::FreshOutputFolder("cli_convert_report");
  SaveRig(folder / "still.frig", test::MakeGridRig(4, 0));
  const fs::path glb = folder / "still.glb", report_path = folder / "still.json";
  const test::CommandOutcome outcome = test::RunCommand(
      cli::RunFacerig, {"convert", (folder / "still.frig").string(), glb.string(), "--json", report_path.string()});
  INFO(outcome.error_output);
  REQUIRE(outcome.exit_code == 0);
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(report_path));
  test::CheckCommandReport(report, "convert");
  CHECK(report["inputs"][0]["path"] == (folder / "still.frig").string());
  CHECK(report["outputs"] == nlohmann::json::array({{{"role", "rig"}, {"path", glb.string()}}}));
  // Every warning printed is in the report: the rig's, and the ARKit names it lacks (--names arkit).
  REQUIRE(report["warnings"].size() == 3);
  CHECK(report["warnings"][0]["code"] == "cannot_speak");
  CHECK(report["warnings"][2]["code"] == "missing_arkit_shapes");
  for (const nlohmann::json& warning : report["warnings"]) {
    CHECK(CountOccurrences(outcome.error_output, "facerig: warning: " + warning["message"].get<std::string>()) == 1);
  }
  CHECK(CountOccurrences(outcome.error_output, "facerig: warning: ") == 3);
  CHECK(report["result"]["vertices"] == LoadRig(glb).vertex_count());
  CHECK(report["result"]["bytes"] == fs::file_size(glb));

  // The report is one of the set: a failed report write leaves neither file.
  fs::remove(glb);
  fs::remove(report_path);
  setenv("FACERIG_INJECT_FAILURE", "fail-report", 1);
  const test::CommandOutcome failed = test::RunCommand(
      cli::RunFacerig, {"convert", (folder / "still.frig").string(), glb.string(), "--json", report_path.string()});
  unsetenv("FACERIG_INJECT_FAILURE");
  CHECK(failed.exit_code == 1);
  CHECK(!fs::exists(glb));
  CHECK(!fs::exists(report_path));
}

TEST_CASE("facerig report: one schema, files not given left out", "[cli]") {
  cli::CommandReport report{"convert", {{"rig", "in.frig"}, {"landmarks", ""}}, {{"rig", "out.glb"}}};
  report.warnings.push_back({"cannot_blink", "no blinks"});
  report.timings = {{"load", 0.25}, {"total", 0.5}};
  report.result["vertices"] = 16;
  const nlohmann::json json = nlohmann::json::parse(cli::ToJson(report).dump());
  test::CheckCommandReport(json, "convert");
  CHECK(json["inputs"] == nlohmann::json::array({{{"role", "rig"}, {"path", "in.frig"}}}));
  CHECK(json["warnings"][0]["message"] == "no blinks");
  CHECK(json["timings"]["load"] == 0.25);
  CHECK(json["result"]["vertices"] == 16);
  CHECK(json.size() == 8);  // schema, command, version, inputs, outputs, warnings, timings, result
  CHECK(cli::ToJson(report).begin().key() == "schema");  // written in the documented order
}

}  // namespace facerig
