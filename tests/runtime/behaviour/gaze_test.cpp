#include "facerig/runtime/behaviour/gaze.h"

#include <cmath>
#include <limits>
#include <vector>

#include <catch2/catch.hpp>

#include "measure/allocation_counter.h"

using facerig::GazeChannels;
using facerig::GazeError;
using facerig::GazeJob;
using facerig::GazeParams;
using facerig::GazeState;
using facerig::Seconds;

namespace {

// Gaze channels at 60 fps over `seconds`, one entry per frame.
std::vector<GazeChannels> Run(std::uint64_t seed, double seconds, const GazeParams& params = {}) {
  GazeState state(seed);
  GazeChannels channels{};
  GazeJob job{&params, &state, Seconds(0.0), &channels};
  std::vector<GazeChannels> frames;
  for (int frame = 0; frame < static_cast<int>(seconds * 60); ++frame) {
    job.time = Seconds(frame / 60.0);
    REQUIRE(job.Run() == GazeError::kNone);
    frames.push_back(channels);
  }
  return frames;
}

}  // namespace

TEST_CASE("Gaze: deterministic for a seed, different across seeds, a seek restarts it", "[gaze]") {
  const std::vector<GazeChannels> a = Run(3, 20.0);
  REQUIRE(a == Run(3, 20.0));
  REQUIRE(a != Run(4, 20.0));

  const GazeParams params;
  GazeState state(3);
  GazeChannels channels{};
  GazeJob job{&params, &state, Seconds(0.0), &channels};
  for (int frame = 0; frame < 600; ++frame) {
    job.time = Seconds(frame / 60.0);
    REQUIRE(job.Run() == GazeError::kNone);
  }
  // Back to the start: the same sequence again, as a fresh state would give.
  for (int frame = 0; frame < 600; ++frame) {
    job.time = Seconds(frame / 60.0);
    REQUIRE(job.Run() == GazeError::kNone);
    REQUIRE(channels == a[static_cast<std::size_t>(frame)]);
  }
}

TEST_CASE("Gaze: bounded, eyes move together, saccades are quick and rare", "[gaze]") {
  const GazeParams params;
  const std::vector<GazeChannels> frames = Run(11, 60.0, params);
  int moving_frames = 0;
  bool moved = false;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const GazeChannels& c = frames[f];
    for (float w : c) REQUIRE((w >= 0.0f && w <= params.amplitude));
    // Looking right: the left eye looks in and the right eye out, by the same amount.
    REQUIRE(c[facerig::kLookInL] == c[facerig::kLookOutR]);
    REQUIRE(c[facerig::kLookOutL] == c[facerig::kLookInR]);
    REQUIRE(c[facerig::kLookUpL] == c[facerig::kLookUpR]);
    REQUIRE(c[facerig::kLookDownL] == c[facerig::kLookDownR]);
    // Never both directions of one axis.
    REQUIRE((c[facerig::kLookInL] == 0.0f || c[facerig::kLookOutL] == 0.0f));
    REQUIRE((c[facerig::kLookUpL] == 0.0f || c[facerig::kLookDownL] == 0.0f));
    if (f > 0 && c != frames[f - 1]) ++moving_frames;
    moved = moved || c != GazeChannels{};
  }
  REQUIRE(moved);
  // At most ~3 frames of motion per saccade (40 ms), a saccade every >= 0.5 s.
  REQUIRE(moving_frames <= 3 * 120);
  REQUIRE(moving_frames > 0);
}

TEST_CASE("Gaze: disabled writes zeros, Run allocates nothing", "[gaze][allocation]") {
  GazeParams off;
  off.enabled = false;
  for (const GazeChannels& c : Run(5, 10.0, off)) REQUIRE(c == GazeChannels{});

  const GazeParams params;
  GazeState state(5);
  GazeChannels channels{};
  GazeJob job{&params, &state, Seconds(0.0), &channels};
  facerig::test::AllocationCounter counter;
  for (int frame = 0; frame < 3600; ++frame) {
    job.time = Seconds(frame / 60.0);
    REQUIRE(job.Run() == GazeError::kNone);
  }
  REQUIRE(counter.count() == 0);
}

TEST_CASE("GazeJob invalid inputs leave everything untouched", "[gaze][malformed]") {
  const GazeParams params;
  GazeState state(1);
  GazeChannels channels;
  channels.fill(7.0f);
  const GazeChannels untouched = channels;
  REQUIRE(GazeJob{nullptr, &state, Seconds(0.0), &channels}.Run() == GazeError::kNoParams);
  REQUIRE(GazeJob{&params, nullptr, Seconds(0.0), &channels}.Run() == GazeError::kNoState);
  REQUIRE(GazeJob{&params, &state, Seconds(0.0), nullptr}.Run() == GazeError::kNoOutput);
  REQUIRE(GazeJob{&params, &state, Seconds(std::numeric_limits<double>::quiet_NaN()), &channels}.Run() ==
          GazeError::kNonFiniteTime);
  GazeParams bad = params;
  bad.saccade_min_interval = 0.0;
  REQUIRE(GazeJob{&bad, &state, Seconds(0.0), &channels}.Run() == GazeError::kInvalidParams);
  bad = params;
  bad.saccade_max_interval = 0.1;  // below the minimum
  REQUIRE(GazeJob{&bad, &state, Seconds(0.0), &channels}.Run() == GazeError::kInvalidParams);
  bad = params;
  bad.amplitude = std::numeric_limits<float>::quiet_NaN();
  REQUIRE(GazeJob{&bad, &state, Seconds(0.0), &channels}.Run() == GazeError::kInvalidParams);
  REQUIRE(channels == untouched);
  REQUIRE(std::string(facerig::ToString(GazeError::kInvalidParams)).find("gaze") != std::string::npos);
}
