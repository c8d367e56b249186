// Rigs that cannot speak or blink are named once, by one check
// (rig_warnings.h) that the player, `facerig inspect` and the reports share.
#include "facerig/runtime/rig_warnings.h"

#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "support/test_meshes.h"

namespace facerig {
namespace {

std::vector<std::string> Codes(const std::vector<RigWarning>& warnings) {
  std::vector<std::string> codes;
  for (const RigWarning& warning : warnings) codes.push_back(warning.code);
  return codes;
}

}  // namespace

TEST_CASE("Rig warnings: a rig without mouth and blink shapes can neither speak nor blink", "[rig_warnings]") {
  const std::vector<RigWarning> none = SpeechAndBlinkWarnings(test::MakeGridRig(4, 0));
  REQUIRE(Codes(none) == std::vector<std::string>{"cannot_speak", "cannot_blink"});
  CHECK(none[0].message ==
        "the rig cannot speak: it has no mouth, jaw or viseme shapes (e.g. jawOpen, mouthClose, viseme_aa), so "
        "speech leaves the face still");
  CHECK(none[1].message == "the rig cannot blink: it has no blink shapes (eyeBlink_L, eyeBlink_R)");
  // Shapes with other names do not help.
  CHECK(Codes(SpeechAndBlinkWarnings(test::MakeNamedGridRig({"browInnerUp", "cheekPuff"}))) ==
        std::vector<std::string>{"cannot_speak", "cannot_blink"});
}

TEST_CASE("Rig warnings: one mouth, jaw or viseme shape is speech, one blink shape is a blink", "[rig_warnings]") {
  CHECK(Codes(SpeechAndBlinkWarnings(test::MakeNamedGridRig({"jawOpen"}))) ==
        std::vector<std::string>{"cannot_blink"});
  // Per-viseme targets count when the rig has most of them (viseme_mapping.h).
  CHECK(Codes(SpeechAndBlinkWarnings(test::MakeNamedGridRig(
            {"viseme_PP", "viseme_FF", "viseme_TH", "viseme_DD", "viseme_kk", "viseme_CH", "viseme_SS",
             "viseme_aa"}))) == std::vector<std::string>{"cannot_blink"});
  CHECK(Codes(SpeechAndBlinkWarnings(test::MakeNamedGridRig({"eyeBlinkLeft"}))) ==
        std::vector<std::string>{"cannot_speak"});
  CHECK(SpeechAndBlinkWarnings(test::MakeNamedGridRig({"jawOpen", "eyeBlink_L", "eyeBlink_R"})).empty());
}

}  // namespace facerig
