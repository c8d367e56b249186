#include "facerig/runtime/speech/viseme_track.h"

#include <limits>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "measure/allocation_counter.h"
#include "support/test_meshes.h"

using facerig::Viseme;
using facerig::VisemeKey;
using facerig::VisemeTrack;
using facerig::VisemeTrackError;

using facerig::test::Key;

namespace {

VisemeTrackError MakeFrom(const std::vector<VisemeKey>& keys) {
  VisemeTrack track;
  return VisemeTrack::Make(keys, track);
}

}  // namespace

TEST_CASE("VisemeTrack refuses invalid and unsorted keys where they are added", "[viseme-track][malformed]") {
  REQUIRE(MakeFrom({Key(0.0, 0.1, Viseme::kAA, 1.0f), Key(0.1, 0.2, Viseme::kPP, 1.0f)}) == VisemeTrackError::kNone);
  REQUIRE(MakeFrom({}) == VisemeTrackError::kNone);
  const std::vector<VisemeKey> backwards_start = {Key(0.1, 0.2, Viseme::kAA, 1.0f), Key(0.0, 0.3, Viseme::kPP, 1.0f)};
  REQUIRE(MakeFrom(backwards_start) == VisemeTrackError::kKeysOutOfOrder);
  const std::vector<VisemeKey> nested = {Key(0.0, 0.5, Viseme::kAA, 1.0f), Key(0.1, 0.2, Viseme::kPP, 1.0f)};
  REQUIRE(MakeFrom(nested) == VisemeTrackError::kKeysOutOfOrder);
  const std::vector<VisemeKey> reversed = {Key(0.2, 0.1, Viseme::kAA, 1.0f)};
  REQUIRE(MakeFrom(reversed) == VisemeTrackError::kInvalidKey);
  const std::vector<VisemeKey> nan_start = {Key(std::numeric_limits<double>::quiet_NaN(), 0.1, Viseme::kAA, 1.0f)};
  REQUIRE(MakeFrom(nan_start) == VisemeTrackError::kInvalidKey);
  const std::vector<VisemeKey> strong = {Key(0.0, 0.1, Viseme::kAA, 2.0f)};
  REQUIRE(MakeFrom(strong) == VisemeTrackError::kInvalidKey);
  const std::vector<VisemeKey> unknown = {Key(0.0, 0.1, static_cast<Viseme>(99), 1.0f)};
  REQUIRE(MakeFrom(unknown) == VisemeTrackError::kInvalidKey);
  REQUIRE(std::string(facerig::ToString(VisemeTrackError::kKeysOutOfOrder)).find("sorted") != std::string::npos);
}

TEST_CASE("VisemeTrack: a refused append changes nothing, capacity is fixed", "[viseme-track]") {
  VisemeTrack track(3);
  REQUIRE(track.Append(Key(0.0, 0.1, Viseme::kAA, 1.0f)) == VisemeTrackError::kNone);
  // Checked against the last key only: a key starting before it is refused alone...
  REQUIRE(track.Append(Key(-0.1, 0.2, Viseme::kPP, 1.0f)) == VisemeTrackError::kKeysOutOfOrder);
  // ...and a batch with one bad key is refused whole.
  const std::vector<VisemeKey> batch = {Key(0.1, 0.2, Viseme::kPP, 1.0f), Key(0.2, 0.1, Viseme::kAA, 1.0f)};
  REQUIRE(track.Append(batch) == VisemeTrackError::kInvalidKey);
  REQUIRE(track.size() == 1);
  const std::vector<VisemeKey> three = {Key(0.1, 0.2, Viseme::kPP, 1.0f),
                                        Key(0.2, 0.3, Viseme::kAA, 1.0f),
                                        Key(0.3, 0.4, Viseme::kAA, 1.0f)};
  REQUIRE(track.Append(three) == VisemeTrackError::kFull);
  REQUIRE(track.size() == 1);
  facerig::test::AllocationCounter counter;
  REQUIRE(track.Append(std::span(three).first(2)) == VisemeTrackError::kNone);
  REQUIRE(track.Append(Key(0.4, 0.5, Viseme::kSil, 1.0f)) == VisemeTrackError::kFull);
  REQUIRE(track.size() == 3);
  REQUIRE(track.keys()[1].viseme == Viseme::kPP);
  track.Clear();
  REQUIRE(track.empty());
  REQUIRE(track.Append(Key(0.4, 0.5, Viseme::kSil, 1.0f)) == VisemeTrackError::kNone);
  REQUIRE(counter.count() == 0);
}
