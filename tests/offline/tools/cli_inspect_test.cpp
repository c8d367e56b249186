// `facerig inspect`: a rig that cannot speak or blink is said so once on
// stderr, and in the --json report (rig_warnings.h).
#include "cli_app.h"

#include <filesystem>
#include <fstream>
#include <string>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

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
  REQUIRE(report["warnings"].size() == 2);
  CHECK(report["warnings"][0]["code"] == "cannot_speak");
  CHECK(report["warnings"][1]["code"] == "cannot_blink");
  CHECK(report["warnings"][1]["message"] == "the rig cannot blink: it has no blink shapes (eyeBlink_L, eyeBlink_R)");
  CHECK(report["vertices"] == 16);
  CHECK(report["shapes"].empty());

  // The built-in head speaks and blinks: no warning, an empty list.
  const test::CommandOutcome head = test::RunCommand(
      cli::RunFacerig, {"inspect", FACERIG_DEFAULT_HEAD, "--json", (folder / "head.json").string()});
  REQUIRE(head.exit_code == 0);
  CHECK(head.error_output.find("warning") == std::string::npos);
  const nlohmann::json head_report = nlohmann::json::parse(std::ifstream(folder / "head.json"));
  CHECK(head_report["warnings"].empty());
  CHECK(head_report["shapes"].size() > 10);
}

}  // namespace facerig
