// facerig-player (main.cpp): a rig that cannot speak or blink is said so once,
// and a timing JSON that cannot be written fails the run, keeping the previous set.
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <catch2/catch.hpp>

#include "facerig/runtime/io/rig_file.h"
#include "support/command_runner.h"
#include "support/test_meshes.h"

namespace {

namespace fs = std::filesystem;
using facerig::test::CountOccurrences;

// Runs the headless player with `environment` and `arguments`; returns the exit code and the output.
int RunPlayer(const std::string& environment, const std::string& arguments, std::string* output) {
  const std::string command = environment + " '" FACERIG_PLAYER_EXE "' --headless --size 64x48 --msaa 0 --fps 10 " +
                              arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  char buffer[512];
  while (std::fgets(buffer, sizeof(buffer), pipe) != nullptr) *output += buffer;
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("Player: a rig that cannot speak or blink is warned about once", "[demo]") {
  const fs::path folder = facerig::test::FreshOutputFolder("player_rig_warnings");
  facerig::SaveRig(folder / "still.frig", facerig::test::MakeGridRig(6, 0));
  std::string output;
  const int code = RunPlayer("", "--rig '" + (folder / "still.frig").string() + "' --say hi --duration 0.3 --frames '" +
                                     (folder / "frames").string() + "'",
                             &output);
  INFO(output);
  CHECK(code == 0);
  CHECK(CountOccurrences(output,
                         "facerig-player: warning: the rig cannot speak: it has no mouth, jaw or viseme shapes") == 1);
  CHECK(CountOccurrences(output, "facerig-player: warning: the rig cannot blink: it has no blink shapes") == 1);

  std::string head_output;
  CHECK(RunPlayer("", "--duration 0.2 --frames '" + (folder / "head_frames").string() + "'", &head_output) == 0);
  INFO(head_output);
  CHECK(head_output.find("warning: the rig") == std::string::npos);
}

TEST_CASE("Player: a timing JSON that cannot be written fails the run and keeps the previous set", "[demo]") {
  const fs::path folder = facerig::test::FreshOutputFolder("player_timing_failure");
  fs::create_directories(folder / "frames");
  std::ofstream(folder / "frames" / "frame_00000.png") << "old frame";
  std::ofstream(folder / "timing.json") << "old timing";
  std::string output;
  const int code = RunPlayer("FACERIG_PLAYER_INJECT_FAILURE=timing",
                             "--duration 0.2 --frames '" + (folder / "frames").string() + "' --timing '" +
                                 (folder / "timing.json").string() + "'",
                             &output);
  INFO(output);
  CHECK(code == 1);
  CHECK(output.find("cannot write timing JSON " + (folder / "timing.json").string() +
                    ": No space left on device; the previous outputs are unchanged") != std::string::npos);
  std::ifstream timing(folder / "timing.json");
  CHECK(std::string(std::istreambuf_iterator<char>(timing), {}) == "old timing");
  CHECK(fs::exists(folder / "frames" / "frame_00000.png"));
  for (const auto& entry : fs::directory_iterator(folder)) {
    CHECK(entry.path().filename().string().rfind(".facerig-tmp-", 0) != 0);
  }
}
