#include "facerig/runtime/alignment/release_landmark.h"

#include <vector>

#include <catch2/catch.hpp>

namespace facerig {
namespace {

Phoneme Make(const char* symbol, double start, double duration) {
  Phoneme p;
  p.symbol.assign(symbol);
  p.start = Seconds(start);
  p.duration = Seconds(duration);
  return p;
}

}  // namespace

TEST_CASE("SteepestRise: the largest step up inside the range, placed between frames", "[release_landmark]") {
  // A closure (quiet) released into a vowel between frames 4 and 5, a
  // smaller rise between frames 1 and 2.
  const std::vector<float> energy = {-9.0f, -9.0f, -7.0f, -8.0f, -8.0f, -2.0f, -2.0f, -2.0f};
  const auto rise = SteepestRise(energy, 0.0, 7.0);
  REQUIRE(rise);
  CHECK(rise->rise == Approx(6.0));
  CHECK(rise->position == Approx(4.5).margin(0.25));
  // Outside the range the release is not seen.
  const auto early = SteepestRise(energy, 0.0, 3.0);
  REQUIRE(early);
  CHECK(early->rise == Approx(2.0));
  CHECK(early->position == Approx(1.5).margin(0.5));
  CHECK_FALSE(SteepestRise(energy, 3.0, 2.0));
  CHECK_FALSE(SteepestRise(std::vector<float>{1.0f}, 0.0, 1.0));
}

TEST_CASE("SteepestRise: a ramp over two frames is placed between them", "[release_landmark]") {
  const std::vector<float> energy = {-8.0f, -8.0f, -5.0f, -2.0f, -2.0f};
  const auto rise = SteepestRise(energy, 0.0, 4.0);
  REQUIRE(rise);
  CHECK(rise->position == Approx(2.0).margin(0.01));
}

TEST_CASE("ReleaseTime and IsBilabial: /p/ releases at its start, /b m/ at their end", "[release_landmark]") {
  CHECK(IsBilabial(Make("p", 0.1, 0.03), "en-us"));
  CHECK(IsBilabial(Make("b", 0.1, 0.03), "en-us"));
  CHECK(IsBilabial(Make("m", 0.1, 0.03), "en-us"));
  CHECK_FALSE(IsBilabial(Make("t", 0.1, 0.03), "en-us"));
  CHECK_FALSE(IsBilabial(Make("a", 0.1, 0.03), "en-us"));
  CHECK(ReleaseTime(Make("p", 0.1, 0.03), "en-us") == Approx(0.1));
  CHECK(ReleaseTime(Make("b", 0.1, 0.03), "en-us") == Approx(0.13));
  CHECK(ReleaseTime(Make("m", 0.1, 0.08), "en-us") == Approx(0.18));
}

}  // namespace facerig
