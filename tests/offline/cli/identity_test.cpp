// `facerig average`, `facerig caricature` and `facerig morph`, run in-process:
// outputs load back with the right shapes and values; bad input exits 1 (2 for
// usage) with a message naming the problem, and writes nothing.
#include "cli/app.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "facerig/offline/identity/caricature.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/io/rig_file.h"
#include "support/command_runner.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

test::CommandOutcome Run(const std::function<int(int, char**)>& command,
                         const std::vector<std::string>& arguments) {
  return test::RunCommand(command, arguments);
}

float MaxDistance(std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
  REQUIRE(a.size() == b.size());
  float worst = 0.0f;
  for (std::size_t v = 0; v < a.size(); ++v) worst = std::max(worst, glm::length(a[v] - b[v]));
  return worst;
}

// A grid rig with its neutral bent: a face of the grid's topology.
Rig BentGrid(float amount, int shape_count = 3) {
  RawRig raw = test::MakeGridRawRig(8, shape_count);
  for (glm::vec3& p : raw.positions) p.z += amount * std::sin(0.6f * p.x) * std::cos(0.4f * p.y);
  std::optional<Rig> rig = RigBuilder::Build(std::move(raw));
  REQUIRE(rig.has_value());
  return std::move(*rig);
}

using test::DenseDeltas;

}  // namespace

TEST_CASE("facerig average: the mean of rigs and OBJs, aligned or not", "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_average");
  const Rig a = BentGrid(0.5f);
  const Rig b = BentGrid(-0.3f);
  SaveRig(folder / "a.frig", a);
  WriteObj(folder / "b.obj", b);
  // c is b moved as a whole: aligned, it averages like b.
  std::vector<glm::vec3> moved(b.positions().begin(), b.positions().end());
  for (glm::vec3& p : moved) p += glm::vec3(3.0f, -1.0f, 2.0f);
  WriteObj(folder / "c.obj", moved, {}, b.uvs(), b.triangles(), b.parts());

  const fs::path unaligned = folder / "mean.obj";
  test::CommandOutcome outcome =
      Run(cli::RunFacerig, {"average", "-o", unaligned.string(), "--no-align", (folder / "a.frig").string(),
                                   (folder / "b.obj").string()});
  REQUIRE(outcome.exit_code == 0);
  const Rig mean = LoadRig(unaligned);
  REQUIRE(mean.vertex_count() == a.vertex_count());
  CHECK(mean.shape_count() == 0);
  std::vector<glm::vec3> expected(a.vertex_count());
  for (std::size_t v = 0; v < expected.size(); ++v) expected[v] = 0.5f * (a.positions()[v] + b.positions()[v]);
  CHECK(MaxDistance(mean.positions(), expected) < 1e-5f);

  // Aligned (the default), b moved as a whole averages like b itself.
  const fs::path aligned = folder / "mean.frig";
  const fs::path aligned_moved = folder / "mean_moved.frig";
  const fs::path report = folder / "average.json";
  REQUIRE(Run(cli::RunFacerig,
              {"average", "-o", aligned.string(), (folder / "a.frig").string(), (folder / "b.obj").string()})
              .exit_code == 0);
  outcome = Run(cli::RunFacerig, {"average", "-o", aligned_moved.string(), (folder / "a.frig").string(),
                                         (folder / "c.obj").string(), "--json", report.string()});
  REQUIRE(outcome.exit_code == 0);
  CHECK(MaxDistance(LoadRig(aligned_moved).positions(), LoadRig(aligned).positions()) < 1e-4f);
  CHECK(MaxDistance(LoadRig(aligned).positions(), expected) < 0.2f);  // a and b differ in shape, not in pose
  const nlohmann::json json = nlohmann::json::parse(ReadFileText(report));
  CHECK(json["inputs"].size() == 2);
  CHECK(json["result"]["faces"] == 2);
  CHECK(json["result"]["aligned"] == true);
}

TEST_CASE("facerig caricature: factor 0 reproduces the rig, factor 1 doubles its difference", "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_caricature");
  const Rig rig = BentGrid(0.5f);
  const Rig average = BentGrid(0.2f, 0);
  const fs::path rig_path = folder / "rig.frig";
  const fs::path average_path = folder / "average.obj";
  SaveRig(rig_path, rig);
  WriteObj(average_path, average);

  for (const bool keep : {true, false}) {
    INFO((keep ? "--keep-deltas" : "deformation transfer"));
    const fs::path same = folder / (keep ? "same_kept.frig" : "same.glb");
    std::vector<std::string> arguments{
        "caricature", "--rig", rig_path.string(), "--average", average_path.string(), "--factor",
        "0",          "-o",    same.string()};
    if (keep) arguments.push_back("--keep-deltas");
    const test::CommandOutcome outcome = Run(cli::RunFacerig, arguments);
    REQUIRE(outcome.exit_code == 0);
    const Rig result = LoadRig(same);
    std::string difference;
    CHECK(test::RigsEqual(result, rig, keep ? 1e-6f : 1e-4f, &difference));
    INFO(difference);
  }

  const fs::path doubled = folder / "doubled.frig";
  const fs::path report = folder / "caricature.json";
  const test::CommandOutcome outcome =
      Run(cli::RunFacerig,
          {"caricature", "--rig", rig_path.string(), "--average", average_path.string(), "--factor", "1", "-o",
           doubled.string(), "--keep-deltas", "--no-align", "--json", report.string()});
  REQUIRE(outcome.exit_code == 0);
  const Rig result = LoadRig(doubled);
  REQUIRE(result.shape_count() == rig.shape_count());
  std::vector<glm::vec3> expected(rig.vertex_count());
  for (std::size_t v = 0; v < expected.size(); ++v) {
    expected[v] = 2.0f * rig.positions()[v] - average.positions()[v];
  }
  CHECK(MaxDistance(result.positions(), expected) < 1e-4f);
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    CHECK(result.shape_name(s) == rig.shape_name(s));
    CHECK(MaxDistance(DenseDeltas(result, s), DenseDeltas(rig, s)) < 1e-6f);
  }
  const nlohmann::json json = nlohmann::json::parse(ReadFileText(report));
  CHECK(json["result"]["factor"] == 1.0);
  CHECK(json["result"]["expressions"] == "keep-deltas");
  CHECK(json["result"]["shapes"] == rig.shape_count());

  // By default the average is rigidly aligned onto the rig first: moving it changes nothing.
  std::vector<glm::vec3> moved(average.positions().begin(), average.positions().end());
  for (glm::vec3& p : moved) p += glm::vec3(0.0f, 5.0f, -1.0f);
  WriteObj(folder / "moved_average.obj", moved, {}, {}, average.triangles(), {});
  const fs::path from_average = folder / "from_average.frig";
  const fs::path from_moved = folder / "from_moved.frig";
  for (const auto& [input, output] :
       {std::pair{average_path, from_average}, std::pair{folder / "moved_average.obj", from_moved}}) {
    REQUIRE(Run(cli::RunFacerig, {"caricature", "--rig", rig_path.string(), "--average", input.string(),
                                            "--factor", "1", "-o", output.string(), "--keep-deltas"})
                .exit_code == 0);
  }
  CHECK(MaxDistance(LoadRig(from_moved).positions(), LoadRig(from_average).positions()) < 1e-4f);
  CHECK(MaxDistance(LoadRig(from_moved).positions(), expected) < 0.2f);
}

TEST_CASE("facerig morph: the template's neutral, the target's shapes and identityMorph", "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_morph");
  const Rig template_rig = BentGrid(0.0f);
  const Rig target = BentGrid(0.7f);
  SaveRig(folder / "template.frig", template_rig);
  SaveRig(folder / "target.glb", target);
  const fs::path output = folder / "morph.frig";
  const test::CommandOutcome outcome =
      Run(cli::RunFacerig, {"morph", "--template", (folder / "template.frig").string(), "--target",
                                 (folder / "target.glb").string(), "-o", output.string()});
  REQUIRE(outcome.exit_code == 0);
  const Rig morph = LoadRig(output);
  REQUIRE(morph.shape_count() == target.shape_count() + 1);
  const std::optional<std::size_t> identity = morph.FindShape(kIdentityMorphShape);
  REQUIRE(identity.has_value());
  CHECK(MaxDistance(morph.positions(), template_rig.positions()) < 1e-6f);
  // identityMorph at 1 is the target's neutral.
  const std::vector<glm::vec3> deltas = DenseDeltas(morph, *identity);
  std::vector<glm::vec3> at_one(morph.positions().begin(), morph.positions().end());
  for (std::size_t v = 0; v < at_one.size(); ++v) at_one[v] += deltas[v];
  CHECK(MaxDistance(at_one, target.positions()) < 1e-5f);
  for (std::size_t s = 0; s < target.shape_count(); ++s) {
    const std::optional<std::size_t> same = morph.FindShape(target.shape_name(s));
    REQUIRE(same.has_value());
    CHECK(MaxDistance(DenseDeltas(morph, *same), DenseDeltas(target, s)) < 1e-6f);
  }
}

TEST_CASE("facerig average / caricature / morph: bad input exits 1 or 2, names the problem, writes nothing",
          "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_identity_errors");
  const Rig rig = BentGrid(0.5f);
  const fs::path rig_path = folder / "rig.frig";
  SaveRig(rig_path, rig);
  RawRig small_raw = test::MakeGridRawRig(5, 3);
  std::optional<Rig> small = RigBuilder::Build(std::move(small_raw));
  REQUIRE(small.has_value());
  const fs::path small_path = folder / "small.frig";
  SaveRig(small_path, *small);
  const fs::path out = folder / "out.frig";
  const std::string missing = (folder / "missing.frig").string();

  struct Case {
    const char* what;
    std::function<int(int, char**)> command;
    std::vector<std::string> arguments;
    int exit_code;
    std::string message;  // a part of stderr
  };
  const std::vector<Case> cases = {
      {"factor not a number",
       cli::RunFacerig,
       {"caricature", "--rig", rig_path.string(), "--average", rig_path.string(), "--factor", "big", "-o",
        out.string()},
       2,
       "--factor: 'big' is not a number"},
      {"factor out of range",
       cli::RunFacerig,
       {"caricature", "--rig", rig_path.string(), "--average", rig_path.string(), "--factor", "3.5", "-o",
        out.string()},
       2,
       "facerig caricature: --factor: 3.5 is outside [-1, 3]"},
      {"average of another vertex count",
       cli::RunFacerig,
       {"caricature", "--rig", rig_path.string(), "--average", small_path.string(), "--factor", "1", "-o",
        out.string()},
       1,
       "small.frig has 25 vertices"},
      {"missing rig",
       cli::RunFacerig,
       {"caricature", "--rig", missing, "--average", rig_path.string(), "--factor", "1", "-o", out.string()},
       1,
       "missing.frig"},
      {"OBJ output for a rig",
       cli::RunFacerig,
       {"caricature", "--rig", rig_path.string(), "--average", rig_path.string(), "--factor", "1", "-o",
        (folder / "out.obj").string()},
       2,
       "an OBJ holds no shapes"},
      {"no factor",
       cli::RunFacerig,
       {"caricature", "--rig", rig_path.string(), "--average", rig_path.string(), "-o", out.string()},
       2,
       "--factor is required"},
      {"unwritable folder",
       cli::RunFacerig,
       {"caricature", "--rig", rig_path.string(), "--average", rig_path.string(), "--factor", "1", "-o",
        (folder / "no_such_folder" / "out.frig").string()},
       1,
       "no_such_folder"},
      {"average: mismatched vertex counts",
       cli::RunFacerig,
       {"average", "-o", out.string(), rig_path.string(), small_path.string()},
       1,
       "small.frig has 25 vertices"},
      {"average: one face",
       cli::RunFacerig,
       {"average", "-o", out.string(), rig_path.string()},
       2,
       "facerig average: faces"},
      {"average: missing face",
       cli::RunFacerig,
       {"average", "-o", out.string(), rig_path.string(), missing},
       1,
       "missing.frig"},
      {"morph: mismatched vertex counts",
       cli::RunFacerig,
       {"morph", "--template", rig_path.string(), "--target", small_path.string(), "-o", out.string()},
       1,
       "small.frig has 25 vertices"},
      {"morph: missing target",
       cli::RunFacerig,
       {"morph", "--template", rig_path.string(), "--target", missing, "-o", out.string()},
       1,
       "missing.frig"},
      {"morph: unknown option",
       cli::RunFacerig,
       {"morph", "--template", rig_path.string(), "--target", rig_path.string(), "-o", out.string(), "--fast"},
       2,
       "not expected: --fast"},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    const test::CommandOutcome outcome = Run(c.command, c.arguments);
    CHECK(outcome.exit_code == c.exit_code);
    INFO(outcome.error_output);
    CHECK(outcome.error_output.find(c.message) != std::string::npos);
    CHECK_FALSE(fs::exists(out));
    CHECK_FALSE(fs::exists(folder / "out.obj"));
  }
  // Nothing else (temporary files) was left in the folder.
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(folder)) files += entry.is_regular_file();
  CHECK(files == 2);

  // A morph target that already has identityMorph.
  const fs::path morph = folder / "morph.frig";
  REQUIRE(Run(cli::RunFacerig,
              {"morph", "--template", rig_path.string(), "--target", rig_path.string(), "-o", morph.string()})
              .exit_code == 0);
  const test::CommandOutcome again = Run(cli::RunFacerig, {"morph", "--template", rig_path.string(),
                                                                "--target", morph.string(), "-o", out.string()});
  CHECK(again.exit_code == 1);
  CHECK(again.error_output.find("already has a shape called identityMorph") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
}

}  // namespace facerig
