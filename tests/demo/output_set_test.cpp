// The headless player's outputs as one set (output_set.h): a normal run
// replaces the previous set whole, a failed write or rename, SIGTERM or SIGINT
// leave it as it was, and temporaries of a killed run go at the next run.
#include "output_set.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "facerig/runtime/io/audio_file.h"
#include "media_writer.h"
#include "support/command_runner.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;

const std::string kRig = std::string(FACERIG_SOURCE_DIR) + "/tests/runtime/files/data/reference_v1.frig";

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// A fresh folder holding a "previous set": two frames, a WAV and a timing JSON with known contents.
fs::path MakePreviousSet(const std::string& name) {
  const fs::path out = fs::path(FACERIG_TEST_OUTPUT_DIR) / ("player_set_" + name);
  fs::remove_all(out);
  fs::create_directories(out / "frames");
  WriteText(out / "frames" / "frame_00000.png", "old frame 0");
  WriteText(out / "frames" / "frame_09999.png", "old frame 9999");
  WriteText(out / "speech.wav", "old wav");
  WriteText(out / "timing.json", "old timing");
  return out;
}

void CheckPreviousSetIntact(const fs::path& out) {
  std::vector<std::string> frames;
  for (const auto& entry : fs::directory_iterator(out / "frames")) frames.push_back(entry.path().filename());
  std::sort(frames.begin(), frames.end());
  CHECK(frames == std::vector<std::string>{"frame_00000.png", "frame_09999.png"});
  CHECK(ReadText(out / "frames" / "frame_00000.png") == "old frame 0");
  CHECK(ReadText(out / "speech.wav") == "old wav");
  CHECK(ReadText(out / "timing.json") == "old timing");
}

std::vector<std::string> Temporaries(const fs::path& out) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(out)) {
    const std::string name = entry.path().filename();
    if (name.rfind(facerig::player::kTemporaryPrefix, 0) == 0) names.push_back(name);
  }
  return names;
}

std::vector<std::string> PlayerArguments(const fs::path& out, double duration) {
  return {FACERIG_PLAYER_EXE, "--headless", "--rig", kRig, "--say", "hi", "--size", "64x48", "--msaa", "0",
          "--fps", "10", "--duration", std::to_string(duration), "--frames", (out / "frames").string(),
          "--wav", (out / "speech.wav").string(), "--timing", (out / "timing.json").string()};
}

// Runs the player through the shell with `environment` ("NAME=value ..."); returns the exit code.
int RunPlayer(const fs::path& out, const std::string& environment, std::string* output) {
  std::string command = environment;
  for (const std::string& argument : PlayerArguments(out, 1.0)) command += " '" + argument + "'";
  return facerig::test::RunShell(command, output);
}

// Starts a long player run, waits until its temporary frames folder holds a
// frame, sends `signal` and returns the wait status.
int RunAndSignal(const fs::path& out, int signal) {
  std::vector<std::string> arguments = PlayerArguments(out, 600.0);
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  const std::string log = (out.parent_path() / (out.filename().string() + ".log")).string();
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  REQUIRE(posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ) == 0);
  posix_spawn_file_actions_destroy(&actions);
  const fs::path first_frame =
      out / (std::string(facerig::player::kTemporaryPrefix) + std::to_string(pid) + "-frames") / "frame_00001.png";
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!fs::exists(first_frame) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  CHECK(fs::exists(first_frame));
  kill(pid, signal);
  int status = 0;
  waitpid(pid, &status, 0);
  INFO(ReadText(log));
  return status;
}

}  // namespace

TEST_CASE("Player outputs: a run replaces the whole set and leaves no temporaries", "[demo]") {
  // Also where the file system has no atomic exchange (the previous outputs are set aside a moment).
  const std::string environment = GENERATE(as<std::string>(), "", "FACERIG_PLAYER_INJECT_FAILURE=no-exchange");
  const fs::path out = MakePreviousSet(environment.empty() ? "normal" : "normal_no_exchange");
  std::string output;
  REQUIRE(RunPlayer(out, environment, &output) == 0);
  INFO(environment << ": " << output);
  std::vector<std::string> frames;
  for (const auto& entry : fs::directory_iterator(out / "frames")) frames.push_back(entry.path().filename());
  CHECK(frames.size() == 10);  // 1 s at 10 fps; the old frame_09999.png is gone: replaced, not merged
  CHECK(!fs::exists(out / "frames" / "frame_09999.png"));
  CHECK(facerig::player::ReadPng(out / "frames" / "frame_00000.png").width == 64);
  CHECK(!facerig::ReadAudioFile(out / "speech.wav").samples.empty());
  CHECK(nlohmann::json::parse(ReadText(out / "timing.json"))["frames"] == 10);
  CHECK(Temporaries(out).empty());
}

TEST_CASE("Player outputs: a failed WAV write or rename fails the run and keeps the previous set", "[demo]") {
  for (const std::string failure : {"wav", "rename", "rename,no-exchange"}) {
    const fs::path out = MakePreviousSet("failure_" + failure);
    std::string output;
    const int code = RunPlayer(out, "FACERIG_PLAYER_INJECT_FAILURE=" + failure, &output);
    INFO(failure << ": " << output);
    CHECK(code == 1);
    if (failure == "wav") {
      CHECK(output.find("cannot write WAV " + (out / "speech.wav").string() + ": No space left on device") !=
            std::string::npos);
    } else {
      CHECK(output.find("cannot rename .facerig-tmp-") != std::string::npos);
      CHECK(output.find(" to " + (out / "timing.json").string() + ": ") != std::string::npos);
    }
    CHECK(output.find("the previous outputs are unchanged") != std::string::npos);
    CheckPreviousSetIntact(out);
    CHECK(Temporaries(out).empty());
  }
}

TEST_CASE("Player outputs: SIGTERM or SIGINT part-way keeps the previous set", "[demo]") {
  for (const int signal : {SIGTERM, SIGINT}) {
    const fs::path out = MakePreviousSet(signal == SIGTERM ? "sigterm" : "sigint");
    const int status = RunAndSignal(out, signal);
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 128 + signal);
    CheckPreviousSetIntact(out);
    CHECK(Temporaries(out).empty());
  }
}

TEST_CASE("Player outputs: temporaries of a killed run are removed by the next run", "[demo]") {
  const fs::path out = MakePreviousSet("killed");
  const int status = RunAndSignal(out, SIGKILL);  // no chance to clean up
  CHECK(WIFSIGNALED(status));
  CheckPreviousSetIntact(out);
  CHECK(Temporaries(out).size() == 1);  // its frames folder
  WriteText(out / ".facerig-tmp-999999999-speech.wav", "from a run long gone");
  const std::string live = ".facerig-tmp-1-timing.json";  // process 1 runs: another run's, kept
  WriteText(out / live, "");
  std::string output;
  REQUIRE(RunPlayer(out, "", &output) == 0);
  INFO(output);
  CHECK(Temporaries(out) == std::vector<std::string>{live});
}

TEST_CASE("Player outputs: a frames folder with other files is not replaced", "[demo]") {
  const fs::path out = MakePreviousSet("foreign");
  WriteText(out / "frames" / "notes.txt", "mine");
  std::string output;
  CHECK(RunPlayer(out, "", &output) == 1);
  INFO(output);
  CHECK(output.find("holds notes.txt") != std::string::npos);
  CHECK(ReadText(out / "frames" / "notes.txt") == "mine");
  CHECK(ReadText(out / "speech.wav") == "old wav");
  CHECK(Temporaries(out).empty());
}

namespace {

// Runs the player on the small reference rig with `arguments` (after the common ones); returns the exit code.
int RunPlayerWith(const std::vector<std::string>& arguments, std::string* output) {
  std::string command = "'" FACERIG_PLAYER_EXE "' --headless --rig '" + kRig +
                        "' --say hi --size 64x48 --msaa 0 --fps 10 --duration 1";
  for (const std::string& argument : arguments) command += " '" + argument + "'";
  return facerig::test::RunShell(command, output);
}

bool HasFfmpeg() { return std::system("command -v ffmpeg >/dev/null 2>&1") == 0; }

}  // namespace

TEST_CASE("Player outputs: a WAV, MP4 and timing JSON inside the frames folder go with the frames, as one set",
          "[demo]") {
  const fs::path out = fs::path(FACERIG_TEST_OUTPUT_DIR) / "player_set_inside";
  fs::remove_all(out);
  fs::create_directories(out);
  const fs::path frames = out / "frames";
  std::vector<std::string> arguments{"--frames", frames.string() + "/", "--wav", (frames / "speech.wav").string(),
                                     "--timing", (frames / "timing.json").string()};
  if (HasFfmpeg()) arguments.insert(arguments.end(), {"--mp4", (frames / "out.mp4").string()});
  // Twice: the second run replaces the first's set, its WAV inside the folder included.
  for (int run = 0; run < 2; ++run) {
    std::string output;
    INFO("run " << run);
    REQUIRE(RunPlayerWith(arguments, &output) == 0);
    INFO(output);
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(frames)) names.push_back(entry.path().filename());
    CHECK(std::count_if(names.begin(), names.end(), [](const std::string& name) { return name.rfind("frame_", 0) == 0; }) ==
          10);
    CHECK(std::count(names.begin(), names.end(), "speech.wav") == 1);
    CHECK(std::count(names.begin(), names.end(), "timing.json") == 1);
    CHECK(names.size() == (HasFfmpeg() ? 13u : 12u));
    CHECK(Temporaries(out).empty());
    CHECK(Temporaries(frames).empty());
    // The WAV's line says what the file holds (the lead-in's silence and the speech), once.
    const facerig::AudioClip wav = facerig::ReadAudioFile(frames / "speech.wav");
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.3f s", wav.duration_seconds());
    const std::string wav_line = "wrote " + (frames / "speech.wav").string() + " (" + std::to_string(wav.samples.size()) +
                                 " samples at " + std::to_string(wav.sample_rate) + " Hz, " + seconds + ")\n";
    CHECK(output.find(wav_line) != std::string::npos);
    const std::size_t frames_line = output.find("wrote 10 frames");
    CHECK(frames_line != std::string::npos);
    if (HasFfmpeg()) {
      CHECK(fs::file_size(frames / "out.mp4") > 0);
      // "wrote out.mp4" once, after the frames are rendered and written.
      const std::size_t mp4_line = output.find("wrote " + (frames / "out.mp4").string() + "\n");
      CHECK(mp4_line != std::string::npos);
      CHECK(mp4_line > frames_line);
      CHECK(output.find("out.mp4", mp4_line + 1) == std::string::npos);
    }
  }
}

TEST_CASE("Player outputs: a name clash with the frames or a missing folder fails before rendering", "[demo]") {
  const fs::path out = fs::path(FACERIG_TEST_OUTPUT_DIR) / "player_set_refused";
  fs::remove_all(out);
  fs::create_directories(out);
  const fs::path frames = out / "frames";
  struct Case {
    std::vector<std::string> arguments;
    std::string message;
  };
  const std::vector<Case> cases = {
      {{"--frames", frames.string(), "--wav", (frames / "frame_00003.png").string()},
       (frames / "frame_00003.png").string() + " is inside --frames " + frames.string() +
           " and named like its frame_NNNNN.png files"},
      {{"--frames", frames.string(), "--wav", (out / "missing" / "speech.wav").string()},
       "cannot write " + (out / "missing" / "speech.wav").string() + ": the folder " + (out / "missing").string() +
           " does not exist"},
      {{"--frames", (out / "missing" / "frames").string()},
       "cannot write " + (out / "missing" / "frames").string() + ": the folder " + (out / "missing").string() +
           " does not exist"},
      {{"--frames", frames.string(), "--wav", (frames / "sub" / "speech.wav").string()}, "are inside one another"},
  };
  for (const Case& c : cases) {
    std::string output;
    CHECK(RunPlayerWith(c.arguments, &output) == 1);
    INFO(output);
    CHECK(output.find(c.message) != std::string::npos);
    CHECK(output.find("rig ") == std::string::npos);  // before the rig was loaded, nothing rendered
    CHECK(output.find("OpenGL") == std::string::npos);
    CHECK(!fs::exists(frames));
    CHECK(!fs::exists(out / "missing"));
    CHECK(Temporaries(out).empty());
  }
}
