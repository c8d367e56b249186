// `facerig build --output-dir`: a cast of targets in one run, run in-process.
// The good targets are built exactly as single builds of them; the bad ones
// are reported (their report and the summary) and skipped, and the exit code
// says so.
#include "build_command.h"
#include "cli/app.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/io/rig_file.h"
#include "support/command_runner.h"
#include "support/ict_faces.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

using test::RunBuildCommand;

std::string FileBytes(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

nlohmann::json ReadJson(const fs::path& path) { return nlohmann::json::parse(std::ifstream(path)); }

}  // namespace

TEST_CASE("(shared data) facerig build --output-dir: a cast of ICT identities and two bad targets: the good ones as "
          "single builds make them, the bad ones reported and skipped",
          "[shared-data][cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_build_cast");
  const fs::path ict_frig = folder / "ict.frig";
  SaveRig(ict_frig, test::IctRig());
  const fs::path faces = folder / "faces";
  fs::create_directory(faces);
  for (const char* identity : {"identity000", "identity007"}) {
    fs::copy_file(fs::path(FACERIG_ICT_DIR) / (std::string(identity) + ".obj"), faces / (std::string(identity) + ".obj"));
  }
  // Unreadable: not an OBJ. No face: a flat sheet, where detection finds none.
  std::ofstream(faces / "broken.obj") << "v 1 2\nf 1 2 3 4 5\n";
  const RawRig sheet = RigBuilder::ToRaw(test::MakeGridRig(30, 0));
  WriteObj(faces / "sheet.obj", sheet.positions, {}, {}, sheet.triangles, {});

  const fs::path cast = folder / "cast";
  const test::CommandOutcome outcome = RunBuildCommand({"--template", ict_frig.string(), "--target", faces.string(),
                                              "--output-dir", cast.string(), "--json", (folder / "summary.json").string()});
  INFO(outcome.error_output);
  CHECK(outcome.exit_code == 3);  // some failed
  // The template's tongueOut was made once for the whole cast.
  CHECK(test::CountOccurrences(outcome.error_output, "made one from its part 'gums_and_tongue'") == 1);

  const nlohmann::json summary = ReadJson(folder / "summary.json");
  CHECK(summary["command"] == "build");
  CHECK(summary["result"]["built"] == 2);
  CHECK(summary["result"]["failed"] == 2);
  std::vector<std::string> names, statuses;
  for (const nlohmann::json& target : summary["result"]["targets"]) {
    names.push_back(target["name"]);
    statuses.push_back(target["status"]);
  }
  CHECK(names == std::vector<std::string>{"broken", "identity000", "identity007", "sheet"});
  CHECK(statuses == std::vector<std::string>{"failed", "built", "built", "failed"});
  CHECK(summary["result"]["targets"][0]["error"].get<std::string>().find("broken.obj") != std::string::npos);
  CHECK(summary["result"]["targets"][3]["error"].get<std::string>().find("--landmarks") != std::string::npos);

  // Each bad target's own report holds its error; no rig is written for it.
  for (const char* bad : {"broken", "sheet"}) {
    INFO(bad);
    const nlohmann::json report = ReadJson(cast / (std::string(bad) + ".json"));
    CHECK(report["result"]["status"] == "failed");
    CHECK_FALSE(report["result"]["error"].get<std::string>().empty());
    CHECK_FALSE(fs::exists(cast / (std::string(bad) + ".glb")));
  }

  // The good ones: built, and byte for byte what a single build of each writes.
  for (const char* identity : {"identity000", "identity007"}) {
    INFO(identity);
    const nlohmann::json report = ReadJson(cast / (std::string(identity) + ".json"));
    CHECK(report["result"]["status"] == "built");
    CHECK(report["result"]["landmarks"] == "template topology");
    CHECK(report["result"]["tongue_out_synthesised_from"] == "gums_and_tongue");
    // The same file name: a glTF's node is named after it.
    fs::create_directories(folder / "single");
    const fs::path single = folder / "single" / (std::string(identity) + ".glb");
    const test::CommandOutcome one = RunBuildCommand({"--template", ict_frig.string(), "--target",
                                            (faces / (std::string(identity) + ".obj")).string(), "-o", single.string()});
    REQUIRE(one.exit_code == 0);
    const std::string cast_bytes = FileBytes(cast / (std::string(identity) + ".glb"));
    CHECK(cast_bytes.size() > 1000000);
    CHECK(cast_bytes == FileBytes(single));
    CHECK(LoadRig(single).shape_count() == LoadRig(cast / (std::string(identity) + ".glb")).shape_count());
  }
  for (const auto& entry : fs::directory_iterator(cast)) {
    CHECK(entry.path().filename().string().find(".facerig-tmp") == std::string::npos);
  }
}

TEST_CASE("facerig build: a cast's command line: -o or --output-dir, one target without it, no per-file options",
          "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_build_cast_usage");
  const std::string head = FACERIG_DEFAULT_HEAD;
  const std::string dir = (folder / "cast").string();
  const test::CommandOutcome two = RunBuildCommand({"--template", head, "--target", head, head, "-o", (folder / "a.glb").string()});
  CHECK(two.exit_code == 2);
  CHECK(two.error_output.find("--output-dir") != std::string::npos);
  for (const char* single : {"-o", "--frig", "--landmarks", "--template-topology", "--obj-dir"}) {
    INFO(single);
    const test::CommandOutcome mixed =
        RunBuildCommand({"--template", head, "--target", head, "--output-dir", dir, single, (folder / "x").string()});
    CHECK(mixed.exit_code == 2);
    CHECK(mixed.error_output.find(std::string(single) + ": names one target's file") != std::string::npos);
  }
  CHECK(RunBuildCommand({"--template", head, "--target", head, "-o", (folder / "a.glb").string(), "--format", "frig"}).exit_code ==
        2);
  CHECK(RunBuildCommand({"--template", head, "--target", head, "--output-dir", dir, "--format", "obj"}).exit_code == 2);
  // Two targets of one name would write the same files: refused before any work.
  fs::create_directory(folder / "a");
  fs::create_directory(folder / "b");
  for (const char* sub : {"a", "b"}) std::ofstream(folder / sub / "face.obj") << "v 0 0 0\n";
  const test::CommandOutcome same = RunBuildCommand({"--template", head, "--target", (folder / "a" / "face.obj").string(),
                                           (folder / "b" / "face.obj").string(), "--output-dir", dir});
  CHECK(same.exit_code == 1);
  CHECK(same.error_output.find("two targets are named 'face'") != std::string::npos);
  CHECK(fs::is_empty(dir));
}

}  // namespace facerig
