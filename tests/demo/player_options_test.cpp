// facerig-player's command line (player_options.cpp on CLI11): --help and
// --version on stdout with exit 0, a bad value exits 2 naming the flag.
#include "player_options.h"

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include <catch2/catch.hpp>

#include "support/test_meshes.h"

namespace {

struct Outcome {
  int exit_code = -1;
  std::string output;  // stdout only
};

// Runs facerig-player with `arguments`, stderr discarded unless `with_errors`.
Outcome RunPlayer(const std::string& arguments, bool with_errors = false) {
  const std::string command =
      "'" FACERIG_PLAYER_EXE "' " + arguments + (with_errors ? " 2>&1" : " 2>/dev/null");
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  Outcome outcome;
  char buffer[512];
  while (std::fgets(buffer, sizeof(buffer), pipe) != nullptr) outcome.output += buffer;
  const int status = pclose(pipe);
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return outcome;
}

}  // namespace

TEST_CASE("Player: --help and --version print to stdout and exit 0", "[demo]") {
  const Outcome help = RunPlayer("--help");
  CHECK(help.exit_code == 0);
  CHECK(help.output.find("usage: facerig-player") != std::string::npos);
  // Generated from the option definitions: every option has a description.
  CHECK(facerig::player::OptionsWithoutDescription().empty());
  for (const auto& [option, described] : {std::pair<std::string, std::string>{"--mp4", "mux the frames"},
                                           {"--fps", "frames per second"},
                                           {"--duration", "seconds to render"},
                                           {"--size", "frame size in pixels"},
                                           {"--wav", "the speech as a WAV"}}) {
    INFO(option);
    const std::size_t at = help.output.find("  " + option + " ");
    REQUIRE(at != std::string::npos);
    const std::size_t next = help.output.find("\n  -", at);  // the next option's line
    CHECK(help.output.substr(at, next - at).find(described) != std::string::npos);
  }
  const Outcome version = RunPlayer("--version");
  CHECK(version.exit_code == 0);
  CHECK(version.output == std::string(FACERIG_VERSION) + "\n");
}

TEST_CASE("Player: a bad command line exits 2 with an error naming the flag and the value", "[demo]") {
  for (const auto& [arguments, message] : {std::pair<std::string, std::string>{"--fps abc", "--fps: 'abc' is not a number"},
                                           {"--msaa 3", "--msaa"},
                                           {"--lead-in 99", "--lead-in"},
                                           {"--emotion boredom", "'boredom'"},
                                           {"--emotion joy:5", "--emotion: intensity 5 of 'joy:5' is outside [0, 1]"},
                                           {"--size 10x10", "--size: '10x10'"},
                                           {"--fps 0", "--fps: 0 is outside [0.1, 1000]"},
                                           {"--bogus", "--bogus"},
                                           {"--rig", "--rig"}}) {
    INFO(arguments);
    const Outcome outcome = RunPlayer(arguments, true);
    CHECK(outcome.exit_code == 2);
    CHECK(outcome.output.find(message) != std::string::npos);
    CHECK(outcome.output.find("facerig-player --help") != std::string::npos);
  }
}

TEST_CASE("Player: options keep their defaults and take every value form", "[demo]") {
  using facerig::player::ParseOptions;
  using facerig::player::UsageError;
  const facerig::player::PlayerOptions defaults = ParseOptions({});
  CHECK(defaults.fps == 30.0);
  CHECK(defaults.msaa == 4);
  CHECK(defaults.lead_in == 0.3);
  CHECK(defaults.voice == "en-us");
  CHECK(!defaults.duration);
  const facerig::player::PlayerOptions options =
      ParseOptions({"--emotion", "joy", "--emotion", "anger:0.2", "--msaa", "0", "--duration", "2.5", "--still",
                    "--quit-after", "1", "--voice=de"});
  REQUIRE(options.emotions.size() == 2);
  CHECK(options.emotions[0].second == 0.7f);
  CHECK(options.emotions[1].second == 0.2f);
  CHECK(options.msaa == 0);
  CHECK(options.duration == 2.5);
  CHECK(options.still);
  CHECK(options.quit_after == 1.0);
  CHECK(options.voice == "de");
  CHECK(ParseOptions({"-h"}).help);
  CHECK(ParseOptions({"--version"}).version);
  CHECK_THROWS_AS(ParseOptions({"--fps", "0"}), UsageError);
  CHECK_THROWS_AS(ParseOptions({"--duration", "-1"}), UsageError);
  CHECK_THROWS_AS(ParseOptions({"--quit-after", "-1"}), UsageError);
  CHECK_THROWS_AS(ParseOptions({"--fps", "nan"}), UsageError);
  CHECK(defaults.yaw_degrees == 0.0f);
  const facerig::player::PlayerOptions turned = ParseOptions({"--yaw", "-35", "--pitch", "10"});
  CHECK(turned.yaw_degrees == -35.0f);
  CHECK(turned.pitch_degrees == 10.0f);
  CHECK_THROWS_AS(ParseOptions({"--yaw", "200"}), UsageError);
  CHECK_THROWS_AS(ParseOptions({"--pitch", "90"}), UsageError);
}

TEST_CASE("Player: the default rig is the head installed beside the executable, else the build tree's", "[demo]") {
  namespace fs = std::filesystem;
  using facerig::player::DefaultRigPath;
  const fs::path prefix = facerig::test::FreshOutputFolder("player_installed_prefix");
  const fs::path executable = prefix / "bin" / "facerig-player";
  const fs::path installed_head = (executable.parent_path() / FACERIG_INSTALLED_HEAD_FROM_BINDIR).lexically_normal();
  CHECK(installed_head.string().rfind(prefix.string(), 0) == 0);  // inside the prefix, not an absolute path
  // Nothing installed: the head the build generated.
  CHECK(DefaultRigPath(executable) == fs::path(FACERIG_DEFAULT_HEAD));
  CHECK(DefaultRigPath(fs::path()) == fs::path(FACERIG_DEFAULT_HEAD));
  fs::create_directories(installed_head.parent_path());
  std::ofstream(installed_head) << "a head";
  CHECK(DefaultRigPath(executable) == installed_head);
  // Run from the build tree (this test binary), nothing is installed beside it.
  CHECK(DefaultRigPath() == fs::path(FACERIG_DEFAULT_HEAD));
}
