// Every `facerig` command checks that each of its outputs can be written
// before it reads or computes anything, and the same way: an output's folder
// must exist (missing folders are an error, never made), the error names the
// path as given. And the progress bars in a log file: one line per stage.
#include "cli/app.h"

#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "cli/common.h"
#include "facerig/runtime/io/rig_file.h"
#include "output_set_files.h"
#include "support/command_runner.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

}  // namespace

TEST_CASE("facerig: an output in a missing folder fails before any work, naming it, and no folder is made", "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_missing_output_folder");
  const std::string rig = (folder / "rig.frig").string();
  SaveRig(rig, test::MakeGridRig(5, 2));
  const fs::path missing = folder / "missing";
  const std::string absent_input = (folder / "no_such_input.obj").string();  // the output is checked first
  struct Case {
    std::vector<std::string> arguments;
    fs::path output;  // the one in the missing folder
  };
  const std::vector<Case> cases = {
      {{"convert", rig, (missing / "out.glb").string()}, missing / "out.glb"},
      {{"convert", rig, (folder / "ok.glb").string(), "--json", (missing / "r.json").string()}, missing / "r.json"},
      {{"convert", absent_input, (missing / "objs").string() + "/"}, missing / "objs/"},
      {{"inspect", rig, "--json", (missing / "r.json").string()}, missing / "r.json"},
      {{"default-head", (missing / "head").string()}, missing / "head"},
      {{"default-head", (folder / "head").string(), "--preview", (missing / "previews").string()},
       missing / "previews"},
      {{"average", "-o", (missing / "avg.frig").string(), rig, rig}, missing / "avg.frig"},
      {{"caricature", "--rig", absent_input, "--average", rig, "--factor", "1", "-o", (missing / "c.frig").string()},
       missing / "c.frig"},
      {{"morph", "--template", rig, "--target", absent_input, "-o", (missing / "m.frig").string()},
       missing / "m.frig"},
      {{"build", "--template", absent_input, "--target", absent_input, "-o", (missing / "b.glb").string()},
       missing / "b.glb"},
      {{"build", "--template", absent_input, "--target", absent_input, "-o", (folder / "b.glb").string(), "--obj-dir",
        (missing / "objs").string()},
       missing / "objs"},
      {{"photo", absent_input, "-o", (missing / "p.glb").string()}, missing / "p.glb"},
      {{"landmarks", absent_input, "-o", (missing / "lm.json").string()}, missing / "lm.json"},
      {{"register", "--template", absent_input, "--target", absent_input, "-o", (missing / "fit.obj").string()},
       missing / "fit.obj"},
  };
  for (const Case& c : cases) {
    INFO(c.arguments[0] << " " << c.output);
    const test::CommandOutcome outcome = test::RunCommand(cli::RunFacerig, c.arguments);
    INFO(outcome.error_output);
    CHECK(outcome.exit_code == 1);
    CHECK(outcome.error_output.find("cannot write " + c.output.string() + ": the folder " + missing.string() +
                                    " does not exist") != std::string::npos);
    CHECK(outcome.error_output.find("no_such_input") == std::string::npos);  // failed before reading
    CHECK_FALSE(fs::exists(missing));
  }
  // default-head left no head folder either, as its --preview could not be written.
  CHECK_FALSE(fs::exists(folder / "head"));
  CHECK(test::Temporaries(folder).empty());
}

TEST_CASE("facerig: an output under a file that is not a folder names the path as given", "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_output_under_file");
  const std::string rig = (folder / "rig.frig").string();
  SaveRig(rig, test::MakeGridRig(5, 0));
  const test::CommandOutcome outcome =
      test::RunCommand(cli::RunFacerig, {"convert", rig, (folder / "rig.frig" / "out.glb").string()});
  CHECK(outcome.exit_code == 1);
  CHECK(outcome.error_output == "facerig: cannot write " + (folder / "rig.frig" / "out.glb").string() + ": " + rig +
                                    " is not a folder\n");
}

TEST_CASE("facerig default-head: OUT_DIR is made when its parent exists", "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_default_head_out_dir");
  const test::CommandOutcome outcome =
      test::RunCommand(cli::RunFacerig, {"default-head", (folder / "made").string(), "--names", "keep"});
  INFO(outcome.error_output);
  REQUIRE(outcome.exit_code == 0);
  CHECK(fs::exists(folder / "made" / "default_head.frig"));
}

TEST_CASE("facerig: progress bars in a log file are one line per stage", "[cli]") {
  // CaptureOutput sends stderr to a file: not a terminal.
  const std::string log = test::CaptureOutput(stderr, "cli_progress_log", [] {
    for (std::size_t done = 0; done <= 4; ++done) cli::ProgressBar("register", done, 4);
    for (std::size_t done = 0; done <= 2; ++done) cli::ProgressBar("transfer", done, 2);
  });
  CHECK(log == "register: 4/4 done\ntransfer: 2/2 done\n");
}

}  // namespace facerig
