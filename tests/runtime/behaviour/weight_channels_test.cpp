#include "facerig/runtime/behaviour/weight_channels.h"

#include <limits>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "measure/allocation_counter.h"

using facerig::ChannelLayer;
using facerig::ChannelRule;
using facerig::ChannelValue;
using facerig::CombineChannelsError;
using facerig::CombineChannelsJob;

TEST_CASE("CombineChannelsJob: add clamps, max keeps the larger, small weights drop", "[weight-channels]") {
  const std::vector<float> base = {0.2f, 0.9f, 0.5f, 0.0005f, 0.0f};
  const std::vector<ChannelValue> blink = {{0, 0.1f}, {2, 0.8f}};
  const std::vector<ChannelValue> gaze = {{1, 0.3f}, {2, 0.1f}, {4, 0.25f}};
  const std::vector<ChannelLayer> layers = {{ChannelRule::kMax, blink}, {ChannelRule::kAdd, gaze}};
  std::vector<float> out(base.size(), -1.0f);
  CombineChannelsJob job{base, layers, 1e-3f, out};
  facerig::test::AllocationCounter counter;
  REQUIRE(job.Run() == CombineChannelsError::kNone);
  REQUIRE(counter.count() == 0);
  REQUIRE(out[0] == 0.2f);                     // max(0.2, 0.1)
  REQUIRE(out[1] == 1.0f);                     // 0.9 + 0.3, clamped
  REQUIRE(out[2] == Approx(0.9f));             // max(0.5, 0.8) + 0.1: layers in order
  REQUIRE(out[3] == 0.0f);                     // below zero_below
  REQUIRE(out[4] == 0.25f);

  // In place (base aliases the output) gives the same.
  std::vector<float> in_place = base;
  REQUIRE(CombineChannelsJob{in_place, layers, 1e-3f, in_place}.Run() == CombineChannelsError::kNone);
  REQUIRE(in_place == out);
}

TEST_CASE("CombineChannelsJob invalid inputs leave the output untouched", "[weight-channels][malformed]") {
  const std::vector<float> base = {0.2f, 0.4f};
  std::vector<float> out = {7.0f, 7.0f};
  const std::vector<float> untouched = out;
  const auto run = [&](std::span<const float> b, std::vector<ChannelValue> values) {
    const ChannelLayer layer{ChannelRule::kAdd, values};
    return CombineChannelsJob{b, std::span(&layer, 1), 0.0f, out}.Run();
  };
  REQUIRE(run(std::vector<float>{0.1f}, {}) == CombineChannelsError::kWeightCountMismatch);
  REQUIRE(run(base, {{2, 0.5f}}) == CombineChannelsError::kShapeOutOfRange);
  REQUIRE(run(base, {{0, 1.5f}}) == CombineChannelsError::kInvalidValue);
  REQUIRE(run(base, {{0, std::numeric_limits<float>::quiet_NaN()}}) == CombineChannelsError::kInvalidValue);
  REQUIRE(run(std::vector<float>{0.1f, std::numeric_limits<float>::infinity()}, {}) ==
          CombineChannelsError::kInvalidValue);
  REQUIRE(out == untouched);
  REQUIRE(std::string(facerig::ToString(CombineChannelsError::kShapeOutOfRange)).find("shape") != std::string::npos);
}
