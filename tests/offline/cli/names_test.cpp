// --names and --visemes on the commands that write rigs, and the ARKit match
// report of `facerig inspect` (cli_names.h).
#include "cli/app.h"

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

bool HasShapeStartingWith(const Rig& rig, std::string_view prefix) {
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    if (rig.shape_name(s).starts_with(prefix)) return true;
  }
  return false;
}

}  // namespace

TEST_CASE("facerig inspect: the built-in head answers all 52 ARKit names and has 15 viseme targets", "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_names_inspect");
  const test::CommandOutcome outcome =
      test::RunCommand(cli::RunFacerig, {"inspect", FACERIG_DEFAULT_HEAD, "--json", (folder / "head.json").string()});
  REQUIRE(outcome.exit_code == 0);
  const nlohmann::json names = nlohmann::json::parse(std::ifstream(folder / "head.json"))["result"]["arkit_match"];
  CHECK(names["arkit_matched"].size() == 52);
  CHECK(names["arkit_missing"].empty());
  for (const nlohmann::json& match : names["arkit_matched"]) CHECK(match["match"] == "exact");
  CHECK(names["viseme_targets"].size() == 15);
  CHECK(names["other"].empty());
}

TEST_CASE("facerig convert: --names ict and keep, --visemes none, and a bad value is a usage error", "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_names_convert");
  const std::string head = FACERIG_DEFAULT_HEAD;  // ARKit names and visemes, as the build writes it
  const fs::path ict = folder / "ict.glb", keep = folder / "keep.frig";
  const test::CommandOutcome to_ict =
      test::RunCommand(cli::RunFacerig, {"convert", head, ict.string(), "--names", "ict", "--visemes", "none"});
  INFO(to_ict.error_output);
  REQUIRE(to_ict.exit_code == 0);
  const Rig ict_rig = LoadRig(ict);
  CHECK(ict_rig.FindShape("eyeBlink_L").has_value());
  CHECK(ict_rig.FindShape("mouthSmile_R").has_value());
  CHECK(ict_rig.FindShape("jawLeft").has_value());
  CHECK_FALSE(ict_rig.FindShape("eyeBlinkLeft").has_value());
  // --visemes none adds none; the head's own baked targets pass through.
  CHECK(ict_rig.FindShape("viseme_PP").has_value());

  test::CommandOutcome kept;
  const std::string printed = test::CaptureOutput(stdout, "cli_names_convert_keep", [&] {
    kept = test::RunCommand(cli::RunFacerig, {"convert", ict.string(), keep.string(), "--names", "keep"});
  });
  REQUIRE(kept.exit_code == 0);
  CHECK(printed.find("shape names keep: 52 of 52 ARKit names; 15 Oculus visemes baked") != std::string::npos);
  const Rig keep_rig = LoadRig(keep);
  CHECK(keep_rig.FindShape("eyeBlink_L").has_value());
  CHECK(keep_rig.shape_count() == ict_rig.shape_count());  // baked again, not added twice

  const test::CommandOutcome bad =
      test::RunCommand(cli::RunFacerig, {"convert", head, (folder / "bad.glb").string(), "--names", "apple"});
  CHECK(bad.exit_code == 2);
  CHECK(bad.error_output.find("'apple' is not arkit, ict or keep") != std::string::npos);
}

TEST_CASE("facerig default-head: --names ict --visemes none writes the head's own ICT-style shapes", "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_names_default_head");
  const test::CommandOutcome outcome =
      test::RunCommand(cli::RunFacerig, {"default-head", folder.string(), "--names", "ict", "--visemes", "none"});
  INFO(outcome.error_output);
  REQUIRE(outcome.exit_code == 0);
  const Rig head = LoadRig(folder / "default_head.glb");
  CHECK(head.FindShape("browInnerUp_L").has_value());  // not merged under ict
  CHECK(head.FindShape("tongueOut").has_value());
  CHECK_FALSE(HasShapeStartingWith(head, "viseme_"));
  CHECK(outcome.error_output.find("warning") == std::string::npos);  // nothing missing
}

}  // namespace facerig
