#include "facerig/runtime/speech/viseme_mapping.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"
#include "facerig/runtime/io/shape_mapping_files.h"
#include "facerig/runtime/rig_builder.h"
#include "measure/allocation_counter.h"
#include "support/test_meshes.h"

using facerig::MappingChannel;
using facerig::Viseme;
using facerig::VisemeMappingStyle;
using facerig::VisemeWeightsJob;
using facerig::VisemeWeightsJobError;

namespace {

// A small grid rig whose shapes carry the given names.
facerig::Rig NamedRig(const std::vector<std::string>& names) { return facerig::test::MakeNamedGridRig(names); }

// Every ARKit mouth shape the built-in mapping uses, in the `Left/Right` style.
std::vector<std::string> ArkitLeftRightNames() {
  return {"jawOpen",          "mouthClose",          "mouthFunnel",        "mouthPucker",
          "mouthRollLower",   "mouthRollUpper",      "mouthPressLeft",     "mouthPressRight",
          "mouthStretchLeft", "mouthStretchRight",   "mouthLowerDownLeft", "mouthLowerDownRight",
          "mouthUpperUpLeft", "mouthUpperUpRight",   "mouthSmileLeft",     "mouthSmileRight",
          "eyeBlinkLeft",     "eyeBlinkRight"};
}

bool HasShape(const facerig::VisemeMapping& m, Viseme v, std::size_t shape) {
  for (const auto& c : m.contributions(v)) {
    if (c.shape == shape) return true;
  }
  return false;
}

bool Mentions(const std::vector<std::string>& warnings, const std::string& text) {
  return std::any_of(warnings.begin(), warnings.end(),
                     [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

}  // namespace

TEST_CASE("FindShapesByArkitName accepts side and namespace styles", "[viseme_mapping]") {
  const facerig::Rig rig = NamedRig({"blendShape1.mouthSmileLeft", "mouthSmile.R", "browInnerUp_L",
                                     "browInnerUp_R", "JAWOPEN", "mouthPucker", "jawLeft"});
  using facerig::FindShapesByArkitName;
  REQUIRE(FindShapesByArkitName(rig, "mouthSmile_L") == std::vector<std::size_t>{0});
  REQUIRE(FindShapesByArkitName(rig, "mouthSmileRight") == std::vector<std::size_t>{1});
  REQUIRE(FindShapesByArkitName(rig, "browInnerUp") == std::vector<std::size_t>{2, 3});
  REQUIRE(FindShapesByArkitName(rig, "jawOpen") == std::vector<std::size_t>{4});
  REQUIRE(FindShapesByArkitName(rig, "mouthPucker_L") == std::vector<std::size_t>{5});
  REQUIRE(FindShapesByArkitName(rig, "jawLeft") == std::vector<std::size_t>{6});
  REQUIRE(FindShapesByArkitName(rig, "mouthFunnel").empty());
  REQUIRE(facerig::IsJawShapeName("jawOpen"));
  REQUIRE(facerig::IsJawShapeName("blendShape1.mouthClose"));
  REQUIRE_FALSE(facerig::IsJawShapeName("mouthSmileLeft"));
}

TEST_CASE("BuildVisemeMapping: TH and DD put the tongue out where the rig has tongueOut, no warning where not",
          "[viseme_mapping]") {
  std::vector<std::string> names = ArkitLeftRightNames();
  names.push_back("tongueOut");
  const facerig::Rig rig = NamedRig(names);
  const facerig::VisemeMappingResult result = facerig::BuildVisemeMapping(rig);
  REQUIRE(result.warnings.empty());
  const std::size_t tongue = *rig.FindShape("tongueOut");
  REQUIRE(HasShape(result.mapping, Viseme::kTH, tongue));
  REQUIRE(HasShape(result.mapping, Viseme::kDD, tongue));
  for (Viseme v : {Viseme::kAA, Viseme::kPP, Viseme::kSS, Viseme::kKK}) REQUIRE_FALSE(HasShape(result.mapping, v, tongue));
  // Without it (ICT-FaceKit itself): the same mapping less the tongue, and no warning.
  REQUIRE(facerig::BuildVisemeMapping(NamedRig(ArkitLeftRightNames())).warnings.empty());
}

TEST_CASE("BuildVisemeMapping on an ARKit Left/Right rig finds every shape", "[viseme_mapping]") {
  const facerig::Rig rig = NamedRig(ArkitLeftRightNames());
  const facerig::VisemeMappingResult result = facerig::BuildVisemeMapping(rig);
  INFO((result.warnings.empty() ? std::string() : result.warnings.front()));
  REQUIRE(result.warnings.empty());
  const facerig::VisemeMapping& m = result.mapping;
  REQUIRE(m.style() == VisemeMappingStyle::kArkit);
  REQUIRE(m.rig_shape_count() == rig.shape_count());
  REQUIRE(m.contributions(Viseme::kSil).empty());
  // PP presses both sides and opens nothing.
  REQUIRE(HasShape(m, Viseme::kPP, *rig.FindShape("mouthPressLeft")));
  REQUIRE(HasShape(m, Viseme::kPP, *rig.FindShape("mouthPressRight")));
  REQUIRE_FALSE(HasShape(m, Viseme::kPP, *rig.FindShape("jawOpen")));
  // FF tucks the lower lip.
  REQUIRE(HasShape(m, Viseme::kFF, *rig.FindShape("mouthRollLower")));
  // Vowels: jawOpen on the jaw channel, aa opens most.
  auto jaw_weight = [&](Viseme v) {
    for (const auto& c : m.contributions(v)) {
      if (c.shape == *rig.FindShape("jawOpen")) {
        REQUIRE(c.channel == MappingChannel::kJaw);
        return c.weight;
      }
    }
    return 0.0f;
  };
  REQUIRE(jaw_weight(Viseme::kAA) > jaw_weight(Viseme::kOH));
  REQUIRE(jaw_weight(Viseme::kOH) > jaw_weight(Viseme::kE));
  REQUIRE(jaw_weight(Viseme::kE) > jaw_weight(Viseme::kIH));
  for (std::size_t v = 0; v < facerig::kVisemeCount; ++v) {
    for (const auto& c : m.contributions(static_cast<Viseme>(v))) {
      REQUIRE(c.shape < rig.shape_count());
      REQUIRE(c.weight > 0.0f);
      REQUIRE(c.weight <= 1.0f);
      if (rig.shape_name(c.shape) != "jawOpen") REQUIRE(c.channel == MappingChannel::kLip);
    }
  }
}

TEST_CASE("BuildVisemeMapping on ICT-FaceKit (shared data)", "[viseme_mapping][shared-data]") {
  const facerig::Rig& rig = facerig::test::IctRig();
  const facerig::VisemeMappingResult result = facerig::BuildVisemeMapping(rig);
  REQUIRE(result.warnings.empty());
  REQUIRE(result.mapping.style() == VisemeMappingStyle::kArkit);
  REQUIRE(HasShape(result.mapping, Viseme::kPP, *rig.FindShape("mouthPress_L")));
  REQUIRE(HasShape(result.mapping, Viseme::kPP, *rig.FindShape("mouthPress_R")));
  for (std::size_t v = 1; v < facerig::kVisemeCount; ++v) {
    REQUIRE_FALSE(result.mapping.contributions(static_cast<Viseme>(v)).empty());
  }
}

TEST_CASE("BuildVisemeMapping on per-viseme rigs", "[viseme_mapping]") {
  SECTION("Oculus names") {
    const facerig::Rig rig = NamedRig({"viseme_sil", "viseme_PP", "viseme_FF", "viseme_TH", "viseme_DD",
                                       "viseme_kk", "viseme_CH", "viseme_SS", "viseme_nn", "viseme_RR",
                                       "viseme_aa", "viseme_E", "viseme_I", "viseme_O", "viseme_U",
                                       "jawOpen"});
    const facerig::VisemeMappingResult result = facerig::BuildVisemeMapping(rig);
    REQUIRE(result.warnings.empty());
    REQUIRE(result.mapping.style() == VisemeMappingStyle::kPerViseme);
    for (std::size_t v = 0; v < facerig::kVisemeCount; ++v) {
      const auto c = result.mapping.contributions(static_cast<Viseme>(v));
      REQUIRE(c.size() == 1);
      REQUIRE(c[0].shape == v);
      REQUIRE(c[0].weight == 1.0f);
    }
    REQUIRE(result.mapping.contributions(Viseme::kAA)[0].channel == MappingChannel::kJaw);
    REQUIRE(result.mapping.contributions(Viseme::kPP)[0].channel == MappingChannel::kLip);
  }
  SECTION("bare names, any case, some missing") {
    const facerig::Rig rig = NamedRig({"pp", "FF", "th", "DD", "KK", "ch", "ss", "NN", "aa", "e", "IH", "oh"});
    const facerig::VisemeMappingResult result = facerig::BuildVisemeMapping(rig);
    REQUIRE(result.mapping.style() == VisemeMappingStyle::kPerViseme);
    REQUIRE(result.mapping.contributions(Viseme::kKK).size() == 1);
    REQUIRE(result.mapping.contributions(Viseme::kRR).empty());
    REQUIRE(Mentions(result.warnings, "viseme RR"));
    REQUIRE(Mentions(result.warnings, "viseme ou"));
    REQUIRE_FALSE(Mentions(result.warnings, "viseme PP"));
  }
}

TEST_CASE("BuildVisemeMapping degrades on rigs missing shapes", "[viseme_mapping]") {
  SECTION("some ARKit shapes missing") {
    const facerig::Rig rig = NamedRig({"jawOpen", "mouthFunnel", "mouthSmile_L"});
    const facerig::VisemeMappingResult result = facerig::BuildVisemeMapping(rig);
    REQUIRE(result.mapping.style() == VisemeMappingStyle::kArkit);
    REQUIRE(Mentions(result.warnings, "mouthPress_L"));
    REQUIRE(Mentions(result.warnings, "mouthPress_R"));
    REQUIRE(Mentions(result.warnings, "viseme PP moves no shape"));
    REQUIRE(result.mapping.contributions(Viseme::kPP).empty());
    REQUIRE(HasShape(result.mapping, Viseme::kAA, 0));
  }
  SECTION("no known shape at all") {
    const facerig::Rig rig = facerig::test::MakeGridRig(5, 3);
    const facerig::VisemeMappingResult result = facerig::BuildVisemeMapping(rig);
    REQUIRE(result.mapping.empty());
    REQUIRE(Mentions(result.warnings, "speech leaves the face at rest"));
    // The job still runs: the face stays at rest.
    std::vector<float> visemes(facerig::kVisemeCount, 0.5f), out(rig.shape_count(), 0.3f);
    VisemeWeightsJob job{&result.mapping, visemes, 1.0f, 1.0f, false, out};
    REQUIRE(job.Run() == VisemeWeightsJobError::kNone);
    for (float w : out) REQUIRE(w == 0.0f);
  }
  SECTION("a rig with no shapes") {
    const facerig::Rig rig = facerig::test::MakeGridRig(4, 0);
    const facerig::VisemeMappingResult result = facerig::BuildVisemeMapping(rig);
    REQUIRE(result.mapping.empty());
    REQUIRE_FALSE(result.warnings.empty());
  }
}

TEST_CASE("Viseme mapping overrides from JSON", "[viseme_mapping]") {
  const facerig::Rig rig = NamedRig(ArkitLeftRightNames());
  const facerig::VisemeMappingOverrides overrides = facerig::ParseVisemeMappingJson(
      R"({"PP": {"mouthClose": 1.0, "jawOpen": 0.1},
          "aa": {"jawOpen": {"weight": 0.7, "channel": "lip"}, "mouthNope": 0.5},
          "ou": {}})",
      "inline");
  facerig::VisemeMappingOptions options;
  options.overrides = &overrides;
  const facerig::VisemeMappingResult result = facerig::BuildVisemeMapping(rig, options);
  const auto pp = result.mapping.contributions(Viseme::kPP);
  REQUIRE(pp.size() == 2);
  for (const auto& c : pp) {
    if (rig.shape_name(c.shape) == "mouthClose") {
      REQUIRE(c.weight == 1.0f);
    } else {
      REQUIRE(rig.shape_name(c.shape) == "jawOpen");
      REQUIRE(c.weight == Approx(0.1f));
    }
    REQUIRE(c.channel == MappingChannel::kJaw);
  }
  const auto aa = result.mapping.contributions(Viseme::kAA);
  REQUIRE(aa.size() == 1);
  REQUIRE(aa[0].weight == Approx(0.7f));
  REQUIRE(aa[0].channel == MappingChannel::kLip);
  REQUIRE(Mentions(result.warnings, "mouthNope"));
  REQUIRE(result.mapping.contributions(Viseme::kOU).empty());  // replaced by an empty list
  REQUIRE_FALSE(result.mapping.contributions(Viseme::kE).empty());  // untouched built-in

  auto error_of = [](const std::string& text) -> std::string {
    try {
      facerig::ParseVisemeMappingJson(text, "map.json");
    } catch (const facerig::IoError& e) {
      REQUIRE(e.kind() == facerig::IoErrorKind::kParse);
      REQUIRE(e.path() == "map.json");
      return e.message();
    }
    return "no error";
  };
  REQUIRE(error_of("{").find("not valid JSON") != std::string::npos);
  REQUIRE(error_of("[1]").find("object") != std::string::npos);
  REQUIRE(error_of(R"({"XX": {}})").find("XX") != std::string::npos);
  REQUIRE(error_of(R"({"PP": 3})").find("PP") != std::string::npos);
  REQUIRE(error_of(R"({"PP": {"mouthClose": "a lot"}})").find("PP.mouthClose") != std::string::npos);
  REQUIRE(error_of(R"({"PP": {"mouthClose": 1.5}})").find("PP.mouthClose: weight outside") != std::string::npos);
  REQUIRE(error_of(R"({"PP": {"mouthClose": {"channel": "jaw"}}})").find("weight") != std::string::npos);
  REQUIRE(error_of(R"({"PP": {"mouthClose": {"weight": 1, "channel": "nose"}}})")
              .find("PP.mouthClose.channel") != std::string::npos);

  // From a file: errors name the file.
  const std::filesystem::path path = facerig::test::OutputPath("viseme_map_bad.json");
  facerig::WriteFileAtomically(path, std::string_view(R"({"aa": {"jawOpen": null}})"));
  try {
    facerig::ReadVisemeMappingFile(path);
    FAIL("expected an IoError");
  } catch (const facerig::IoError& e) {
    REQUIRE(std::string(e.what()).find(path.string()) != std::string::npos);
    REQUIRE(e.message().find("aa.jawOpen") != std::string::npos);
  }
  REQUIRE_THROWS_AS(facerig::ReadVisemeMappingFile(facerig::test::OutputPath("no_such_map.json")),
                    facerig::IoError);
  const std::filesystem::path good = facerig::test::OutputPath("viseme_map_good.json");
  facerig::WriteFileAtomically(good, std::string_view(R"({"FF": {"mouthRollLower": 0.4}})"));
  const facerig::VisemeMappingOverrides read = facerig::ReadVisemeMappingFile(good);
  REQUIRE(read.visemes[static_cast<std::size_t>(Viseme::kFF)]->at(0).weight == Approx(0.4f));
}

TEST_CASE("VisemeWeightsJob writes, accumulates, scales jaw and lip, spares PP and FF",
          "[viseme_mapping]") {
  const facerig::Rig rig = NamedRig(ArkitLeftRightNames());
  const facerig::VisemeMappingResult result = facerig::BuildVisemeMapping(rig);
  const std::size_t jaw = *rig.FindShape("jawOpen");
  const std::size_t lower = *rig.FindShape("mouthLowerDownLeft");
  const std::size_t press = *rig.FindShape("mouthPressLeft");
  const std::size_t blink = *rig.FindShape("eyeBlinkLeft");
  std::vector<float> visemes(facerig::kVisemeCount, 0.0f);
  visemes[static_cast<std::size_t>(Viseme::kAA)] = 1.0f;
  std::vector<float> out(rig.shape_count(), 0.9f);
  VisemeWeightsJob job{&result.mapping, visemes, 1.0f, 1.0f, false, out};
  REQUIRE(job.Run() == VisemeWeightsJobError::kNone);
  REQUIRE(out[jaw] == Approx(0.6f));
  REQUIRE(out[lower] == Approx(0.2f));
  REQUIRE(out[blink] == 0.0f);  // overwritten

  job.jaw_intensity = 0.5f;
  job.lip_intensity = 2.0f;
  REQUIRE(job.Run() == VisemeWeightsJobError::kNone);
  REQUIRE(out[jaw] == Approx(0.3f));
  REQUIRE(out[lower] == Approx(0.4f));

  // PP is not scaled by any intensity.
  std::fill(visemes.begin(), visemes.end(), 0.0f);
  visemes[static_cast<std::size_t>(Viseme::kPP)] = 1.0f;
  job.jaw_intensity = 0.0f;
  job.lip_intensity = 0.0f;
  REQUIRE(job.Run() == VisemeWeightsJobError::kNone);
  REQUIRE(out[press] == Approx(0.3f));

  // Accumulate: adds onto the existing weights, clamps what it touched, leaves the rest.
  std::fill(out.begin(), out.end(), 0.0f);
  out[blink] = 0.7f;
  out[press] = 0.9f;
  job.accumulate = true;
  REQUIRE(job.Run() == VisemeWeightsJobError::kNone);
  REQUIRE(out[blink] == 0.7f);
  REQUIRE(out[press] == 1.0f);

  facerig::test::AllocationCounter counter;
  for (int i = 0; i < 100; ++i) REQUIRE(job.Run() == VisemeWeightsJobError::kNone);
  REQUIRE(counter.count() == 0);
}

TEST_CASE("VisemeWeightsJob invalid inputs", "[viseme_mapping]") {
  const facerig::Rig rig = NamedRig(ArkitLeftRightNames());
  const facerig::VisemeMappingResult result = facerig::BuildVisemeMapping(rig);
  std::vector<float> visemes(facerig::kVisemeCount, 0.1f);
  std::vector<float> out(rig.shape_count(), 0.25f);
  const std::vector<float> untouched = out;
  auto make = [&] { return VisemeWeightsJob{&result.mapping, visemes, 1.0f, 1.0f, false, out}; };

  VisemeWeightsJob job = make();
  job.mapping = nullptr;
  REQUIRE(job.Run() == VisemeWeightsJobError::kNoMapping);
  job = make();
  job.viseme_weights = std::span<const float>(visemes).first(14);
  REQUIRE(job.Run() == VisemeWeightsJobError::kVisemeCountMismatch);
  job.viseme_weights = {};
  REQUIRE(job.Run() == VisemeWeightsJobError::kVisemeCountMismatch);
  job = make();
  job.out_weights = std::span<float>(out).first(out.size() - 1);
  REQUIRE(job.Run() == VisemeWeightsJobError::kWeightCountMismatch);
  job.out_weights = {};
  REQUIRE(job.Run() == VisemeWeightsJobError::kWeightCountMismatch);
  job = make();
  job.jaw_intensity = std::numeric_limits<float>::quiet_NaN();
  REQUIRE(job.Run() == VisemeWeightsJobError::kInvalidIntensity);
  job = make();
  job.lip_intensity = -1.0f;
  REQUIRE(job.Run() == VisemeWeightsJobError::kInvalidIntensity);
  visemes[3] = std::numeric_limits<float>::quiet_NaN();
  job = make();
  REQUIRE(job.Run() == VisemeWeightsJobError::kNonFiniteViseme);
  visemes[3] = 1.5f;
  REQUIRE(job.Run() == VisemeWeightsJobError::kNonFiniteViseme);
  REQUIRE(out == untouched);
  REQUIRE(std::string(facerig::ToString(VisemeWeightsJobError::kWeightCountMismatch)).find("shape count") !=
          std::string::npos);
}
