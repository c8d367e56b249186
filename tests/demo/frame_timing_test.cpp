// The timing JSON writer (frame_timing.h) checks every write and the close: a
// full disk is an error naming the file, and no file is left.
#include "frame_timing.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "support/test_meshes.h"

namespace {

namespace fs = std::filesystem;
using facerig::player::FrameSample;
using facerig::player::TimingSummary;

}  // namespace

TEST_CASE("Timing JSON: written whole, or a full disk is an error and leaves no file", "[demo][timing]") {
  const fs::path folder = facerig::test::FreshOutputFolder("timing_json");
  const fs::path path = folder / "timing.json";
  const TimingSummary summary;
  const std::vector<FrameSample> samples(3);
  facerig::player::WriteTimingJson(path, summary, samples, "rig.frig", 16, 2);
  CHECK(nlohmann::json::parse(std::ifstream(path))["per_frame_ms"].size() == 3);
  CHECK(!nlohmann::json::parse(std::ifstream(path)).contains("timeline"));
  // A headless run says where the WAV and the speech start, in seconds from frame 0.
  facerig::player::WriteTimingJson(path, summary, samples, "rig.frig", 16, 2,
                                   facerig::player::OutputTimeline{.fps = 30.0, .wav_start = 0.0, .speech_start = 0.3});
  const nlohmann::json timeline = nlohmann::json::parse(std::ifstream(path))["timeline"];
  CHECK(timeline["frame0_seconds"] == 0.0);
  CHECK(timeline["wav_start_seconds"] == 0.0);
  CHECK(timeline["speech_start_seconds"] == 0.3);
  CHECK(timeline["fps"] == 30.0);

  fs::remove(path);
  setenv("FACERIG_PLAYER_INJECT_FAILURE", "timing", 1);
  try {
    facerig::player::WriteTimingJson(path, summary, samples, "rig.frig", 16, 2);
    FAIL("no error");
  } catch (const std::runtime_error& error) {
    CHECK(std::string(error.what()) == "cannot write timing JSON " + path.string() + ": No space left on device");
  }
  unsetenv("FACERIG_PLAYER_INJECT_FAILURE");
  CHECK(!fs::exists(path));
}
