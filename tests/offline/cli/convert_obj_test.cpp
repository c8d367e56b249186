// `facerig convert` to OBJ: an OBJ file holds no blend shapes, so a rig with
// shapes is refused as OUT.obj (exit 2, saying what to do), written whole as a
// folder of OBJs (OUT/: neutral.obj and one OBJ per shape, read back as a
// template folder), or written as its neutral alone with --neutral-only, the
// message saying the shapes were not written.
#include "cli/app.h"

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/io/template_folder.h"
#include "facerig/runtime/io/rig_file.h"
#include "output_set_files.h"
#include "support/command_runner.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

struct Printed {
  test::CommandOutcome outcome;
  std::string output;  // stdout
};

Printed Convert(const std::vector<std::string>& arguments) {
  Printed printed;
  std::vector<std::string> command{"convert"};
  command.insert(command.end(), arguments.begin(), arguments.end());
  printed.output = test::CaptureOutput(stdout, "cli_convert_obj_stdout",
                                       [&] { printed.outcome = test::RunCommand(cli::RunFacerig, command); });
  return printed;
}

using test::DenseDeltas;

}  // namespace

TEST_CASE("facerig convert to .obj: a rig with shapes is refused, not written without them", "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_convert_obj_refused");
  SaveRig(folder / "rig.frig", test::MakeGridRig(5, 3));
  const Printed refused = Convert({(folder / "rig.frig").string(), (folder / "rig.obj").string(), "--names", "keep",
                                   "--visemes", "none"});
  INFO(refused.outcome.error_output);
  CHECK(refused.outcome.exit_code == 2);
  CHECK(refused.outcome.error_output.find("an OBJ file holds no blend shapes and the rig has 3") != std::string::npos);
  CHECK(refused.outcome.error_output.find("--neutral-only") != std::string::npos);
  CHECK(refused.outcome.error_output.find((folder / "rig").string() + "/") != std::string::npos);  // the folder form
  CHECK(refused.output.find("wrote") == std::string::npos);
  CHECK(test::Names(folder) == std::vector<std::string>{"rig.frig"});

  // A rig without shapes is an OBJ as before.
  SaveRig(folder / "plain.frig", test::MakeGridRig(5, 0));
  const Printed plain = Convert({(folder / "plain.frig").string(), (folder / "plain.obj").string()});
  CHECK(plain.outcome.exit_code == 0);
  CHECK(LoadRig(folder / "plain.obj").vertex_count() == 25);
}

TEST_CASE("facerig convert --neutral-only to .obj: the neutral, and the message says the shapes were not written",
          "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_convert_obj_neutral");
  const Rig rig = test::MakeGridRig(5, 3);
  SaveRig(folder / "rig.frig", rig);
  const fs::path obj = folder / "rig.obj";
  const Printed neutral = Convert({(folder / "rig.frig").string(), obj.string(), "--neutral-only", "--names", "keep",
                                   "--visemes", "none"});
  INFO(neutral.outcome.error_output);
  REQUIRE(neutral.outcome.exit_code == 0);
  CHECK(neutral.output.find("wrote " + obj.string() + " (25 vertices, 0 shapes,") != std::string::npos);
  CHECK(neutral.output.find("neutral only: the rig's 3 shapes not written") != std::string::npos);
  CHECK(neutral.output.find("units cm, which OBJ does not store (read it back with --units cm)") != std::string::npos);
  const Rig back = LoadRig(obj);
  CHECK(back.vertex_count() == rig.vertex_count());
  CHECK(back.shape_count() == 0);
}

TEST_CASE("facerig convert to a folder: neutral.obj and one OBJ per shape, read back with the same shapes", "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_convert_obj_folder");
  const Rig rig = test::MakeGridRig(6, 4);
  SaveRig(folder / "rig.frig", rig);
  const std::string objs = (folder / "rig_objs").string() + "/";
  const Printed written =
      Convert({(folder / "rig.frig").string(), objs, "--names", "keep", "--visemes", "none"});
  INFO(written.outcome.error_output);
  REQUIRE(written.outcome.exit_code == 0);
  CHECK(written.output.find("wrote " + objs + " (neutral.obj and 4 shape OBJs, 36 vertices each)") != std::string::npos);
  CHECK(test::Names(folder / "rig_objs") ==
        std::vector<std::string>{"neutral.obj", "shape0.obj", "shape1.obj", "shape2.obj", "shape3.obj"});
  CHECK(test::Temporaries(folder).empty());

  // Read back as a template folder (the form facerig reads): every shape, its deltas within OBJ's rounding.
  TemplateImportOptions units;
  units.units = rig.units();
  const Rig back = ImportTemplateFolder(folder / "rig_objs", units);
  REQUIRE(back.shape_count() == rig.shape_count());
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    INFO(rig.shape_name(s));
    const std::optional<std::size_t> same = back.FindShape(rig.shape_name(s));
    REQUIRE(same.has_value());
    const std::vector<glm::vec3> expected = DenseDeltas(rig, s), got = DenseDeltas(back, *same);
    float worst = 0.0f;
    for (std::size_t v = 0; v < expected.size(); ++v) worst = std::max(worst, glm::length(expected[v] - got[v]));
    CHECK(worst < 1e-4f);
  }

  // Written again: the folder is replaced as a whole.
  REQUIRE(Convert({(folder / "rig.frig").string(), objs, "--names", "keep", "--visemes", "none"}).outcome.exit_code ==
          0);
  CHECK(test::Names(folder / "rig_objs").size() == 5);
}

}  // namespace facerig
