#include "facerig/runtime/shape_names.h"

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/runtime/speech/viseme.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

const ArkitShapeMatch* MatchOf(const ShapeNameReport& report, std::string_view arkit) {
  for (const ArkitShapeMatch& match : report.matched) {
    if (match.arkit_name == arkit) return &match;
  }
  return nullptr;
}

}  // namespace

TEST_CASE("Shape names: Apple's 52 ARKit names, and their ICT spelling", "[shape_names]") {
  const std::set<std::string_view> unique(kArkitShapeNames.begin(), kArkitShapeNames.end());
  CHECK(unique.size() == 52);
  for (std::string_view name : {"eyeBlinkLeft", "eyeLookDownRight", "jawForward", "mouthRollUpper",
                                "mouthShrugLower", "browInnerUp", "cheekPuff", "cheekSquintRight", "tongueOut"}) {
    CHECK(unique.contains(name));
  }
  // No two ARKit names mean the same shape once spelling is set aside.
  std::set<std::string> canonical;
  for (std::string_view name : kArkitShapeNames) canonical.insert(CanonicalShapeNameOf(name).full());
  CHECK(canonical.size() == 52);

  CHECK(IctShapeName("eyeBlinkLeft") == "eyeBlink_L");
  CHECK(IctShapeName("mouthUpperUpRight") == "mouthUpperUp_R");
  CHECK(IctShapeName("browInnerUp") == "browInnerUp");
  CHECK(IctShapeName("jawLeft") == "jawLeft");  // a motion, not a side
  CHECK(IctShapeName("mouthRight") == "mouthRight");
}

TEST_CASE("Shape names: the reader maps every common spelling to the ARKit name", "[shape_names]") {
  // One spelling per rig, each answering eyeBlinkLeft, and its side kept apart.
  for (const char* spelling : {"eyeBlinkLeft", "eyeBlink_L", "eyeBlink.L", "EYEBLINK_l", "eyeblinkleft",
                                      "blendShape1.eyeBlinkLeft", "Head:eyeBlink_L", "mesh|eyeBlink.L",
                                      "eyeBlink_Left"}) {
    INFO(spelling);
    const Rig rig = test::MakeNamedGridRig({"eyeBlinkRight", spelling});
    CHECK(FindShapesByArkitName(rig, "eyeBlinkLeft") == std::vector<std::size_t>{1});
    CHECK(FindShapesByArkitName(rig, "eyeBlinkRight") == std::vector<std::size_t>{0});
    const ShapeNameReport report = MatchShapeNames(rig);
    const ArkitShapeMatch* match = MatchOf(report, "eyeBlinkLeft");
    REQUIRE(match);
    CHECK(match->kind == (std::string_view(spelling) == "eyeBlinkLeft" ? ShapeMatchKind::kExact : ShapeMatchKind::kSpelling));
  }
}

TEST_CASE("Shape names: the match report lists matched, missing, viseme and other shapes", "[shape_names]") {
  const Rig rig = test::MakeNamedGridRig({"jawOpen", "browInnerUp_L", "browInnerUp_R", "eyeBlink", "mouthSmile.L",
                                          "viseme_PP", "aa", "identityMorph"});
  const ShapeNameReport report = MatchShapeNames(rig);
  REQUIRE(MatchOf(report, "jawOpen"));
  CHECK(MatchOf(report, "jawOpen")->kind == ShapeMatchKind::kExact);
  REQUIRE(MatchOf(report, "browInnerUp"));
  CHECK(MatchOf(report, "browInnerUp")->kind == ShapeMatchKind::kBothSides);
  CHECK(MatchOf(report, "browInnerUp")->shapes == std::vector<std::size_t>{1, 2});
  REQUIRE(MatchOf(report, "eyeBlinkLeft"));
  CHECK(MatchOf(report, "eyeBlinkLeft")->kind == ShapeMatchKind::kUnsided);
  REQUIRE(MatchOf(report, "mouthSmileLeft"));
  CHECK(MatchOf(report, "mouthSmileLeft")->kind == ShapeMatchKind::kSpelling);
  // jawOpen, browInnerUp, eyeBlinkLeft/Right (both from eyeBlink), mouthSmileLeft.
  CHECK(report.matched.size() == 5);
  CHECK(report.missing.size() == 52 - 5);
  CHECK(std::find(report.missing.begin(), report.missing.end(), "tongueOut") != report.missing.end());
  CHECK(report.viseme_targets == std::vector<std::size_t>{5, 6});
  CHECK(report.other == std::vector<std::size_t>{7});
}

TEST_CASE("Shape names: Oculus viseme targets, and the spellings read as visemes", "[shape_names]") {
  CHECK(OculusTargetName(Viseme::kSil) == "viseme_sil");
  CHECK(OculusTargetName(Viseme::kPP) == "viseme_PP");
  CHECK(OculusTargetName(Viseme::kKK) == "viseme_kk");
  CHECK(OculusTargetName(Viseme::kIH) == "viseme_I");
  CHECK(OculusTargetName(Viseme::kOU) == "viseme_U");
  for (std::size_t v = 0; v < kVisemeCount; ++v) {
    const auto viseme = static_cast<Viseme>(v);
    CHECK(VisemeOfTargetName(OculusTargetName(viseme)) == viseme);
    CHECK(VisemeOfTargetName(ToString(viseme)) == viseme);
  }
  CHECK(VisemeOfTargetName("blendShape1.VISEME_AA") == Viseme::kAA);
  CHECK(VisemeOfTargetName("visemeOH") == Viseme::kOH);
  CHECK(VisemeOfTargetName("viseme_ih") == Viseme::kIH);
  CHECK_FALSE(VisemeOfTargetName("jawOpen").has_value());
  CHECK_FALSE(VisemeOfTargetName("viseme").has_value());
  CHECK_FALSE(VisemeOfTargetName("viseme_XX").has_value());
}

}  // namespace facerig
