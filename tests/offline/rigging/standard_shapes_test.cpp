// The names and viseme targets written rigs carry (standard_shapes.h), on the
// built-in head: each naming mode, the baked visemes against the runtime's
// mapping, and the runtime choosing baked visemes when a rig has them.
#include "facerig/offline/rigging/standard_shapes.h"

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/character.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/runtime/shape_names.h"
#include "facerig/runtime/speech/viseme_mapping.h"
#include "support/default_head_poses.h"
#include "support/gltf_validator.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

std::set<std::string> ShapeNames(const Rig& rig) {
  std::set<std::string> names;
  for (std::size_t s = 0; s < rig.shape_count(); ++s) names.emplace(rig.shape_name(s));
  return names;
}

std::vector<glm::vec3> Blend(const Rig& rig, const std::vector<float>& weights) {
  std::vector<glm::vec3> positions(rig.vertex_count());
  BlendJob job{&rig, weights, NormalMode::kNone, positions, {}};
  REQUIRE(job.Run() == BlendJobError::kNone);
  return positions;
}

float MaxDistance(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  float worst = 0.0f;
  for (std::size_t v = 0; v < a.size(); ++v) worst = std::max(worst, glm::length(a[v] - b[v]));
  return worst;
}

}  // namespace

TEST_CASE("Standard shapes: the built-in head under --names arkit has Apple's names and 15 visemes",
          "[standard_shapes][default_head]") {
  const Rig& head = test::DefaultHead();
  const StandardShapesResult named = StandardizeShapes(head);
  const std::set<std::string> names = ShapeNames(named.rig);
  for (std::string_view arkit : kArkitShapeNames) {
    INFO(arkit);
    CHECK(names.contains(std::string(arkit)));
  }
  CHECK(named.report.arkit_present == 52);
  CHECK(named.report.arkit_missing.empty());
  CHECK(named.report.merged == std::vector<std::string>{"browInnerUp", "cheekPuff"});
  for (std::size_t v = 0; v < kVisemeCount; ++v) CHECK(names.contains(std::string(OculusTargetName(Viseme(v)))));
  CHECK(named.report.visemes_baked == 15);
  // No shape keeps an ICT-style side: every one is ARKit, a viseme or merged away.
  CHECK(named.rig.shape_count() == head.shape_count() - 2 + 15);
  for (const std::string& name : names) CHECK_FALSE((name.ends_with("_L") || name.ends_with("_R")));

  // The merged browInnerUp is the sum of its halves.
  const std::vector<float> none(head.shape_count(), 0.0f);
  std::vector<float> halves = none;
  halves[*head.FindShape("browInnerUp_L")] = 1.0f;
  halves[*head.FindShape("browInnerUp_R")] = 1.0f;
  std::vector<float> merged(named.rig.shape_count(), 0.0f);
  merged[*named.rig.FindShape("browInnerUp")] = 1.0f;
  CHECK(MaxDistance(Blend(head, halves), Blend(named.rig, merged)) < 1e-5f);
}

TEST_CASE("Standard shapes: --names ict and keep", "[standard_shapes][default_head]") {
  const Rig& head = test::DefaultHead();
  const StandardShapesResult ict = StandardizeShapes(head, {ShapeNaming::kIct, VisemeTargets::kOculus});
  const std::set<std::string> ict_names = ShapeNames(ict.rig);
  for (const char* name : {"eyeBlink_L", "eyeBlink_R", "mouthSmile_L", "browInnerUp_L", "cheekPuff_R", "jawOpen",
                           "viseme_PP", "viseme_U"}) {
    CHECK(ict_names.contains(name));
  }
  CHECK_FALSE(ict_names.contains("eyeBlinkLeft"));
  CHECK(ict.report.renamed == 0);  // the head is already in the ICT style
  CHECK(ict.report.arkit_present == 52);

  const StandardShapesResult keep = StandardizeShapes(head, {ShapeNaming::kKeep, VisemeTargets::kNone});
  REQUIRE(keep.rig.shape_count() == head.shape_count());
  for (std::size_t s = 0; s < head.shape_count(); ++s) CHECK(keep.rig.shape_name(s) == head.shape_name(s));

  // An ARKit-named rig back to ICT: the names round-trip, halves stay merged.
  const StandardShapesResult arkit = StandardizeShapes(head);
  const StandardShapesResult back = StandardizeShapes(arkit.rig, {ShapeNaming::kIct, VisemeTargets::kOculus});
  const std::set<std::string> back_names = ShapeNames(back.rig);
  CHECK(back_names.contains("eyeLookUp_R"));
  CHECK(back_names.contains("browInnerUp"));
  CHECK(back.rig.shape_count() == arkit.rig.shape_count());  // visemes baked again, not added twice
}

TEST_CASE("Standard shapes: each baked viseme is the runtime mapping's blend of the head's shapes",
          "[standard_shapes][default_head]") {
  const Rig& head = test::DefaultHead();
  const VisemeMappingResult mapping = BuildVisemeMapping(head);
  REQUIRE(mapping.mapping.style() == VisemeMappingStyle::kArkit);
  const StandardShapesResult named = StandardizeShapes(head);
  float largest_motion = 0.0f;
  for (std::size_t v = 0; v < kVisemeCount; ++v) {
    const auto viseme = static_cast<Viseme>(v);
    INFO(OculusTargetName(viseme));
    std::vector<float> visemes(kVisemeCount, 0.0f), weights(head.shape_count(), 0.0f);
    visemes[v] = 1.0f;
    REQUIRE(VisemeWeightsJob{&mapping.mapping, visemes, 1.0f, 1.0f, false, weights}.Run() ==
            VisemeWeightsJobError::kNone);
    std::vector<float> baked(named.rig.shape_count(), 0.0f);
    baked[*named.rig.FindShape(OculusTargetName(viseme))] = 1.0f;
    const std::vector<glm::vec3> from_mapping = Blend(head, weights);
    CHECK(MaxDistance(from_mapping, Blend(named.rig, baked)) < 1e-5f);
    largest_motion = std::max(largest_motion, MaxDistance(from_mapping, {head.positions().begin(), head.positions().end()}));
  }
  CHECK(largest_motion > 0.5f);  // cm: the visemes move the mouth
  // viseme_PP presses the lips: it is not empty.
  CHECK_FALSE(named.rig.shape(*named.rig.FindShape("viseme_PP")).vertex_indices.empty());
}

TEST_CASE("Standard shapes: the runtime speaks through baked visemes, else through the mapping",
          "[standard_shapes][default_head]") {
  const Rig& head = test::DefaultHead();
  const Rig named = StandardizeShapes(head).rig;
  const std::vector<Phoneme> line = {test::MakePhoneme(0.00, 0.10, "_:"), test::MakePhoneme(0.10, 0.20, "A:"),
                                     test::MakePhoneme(0.30, 0.08, "p"), test::MakePhoneme(0.38, 0.20, "A:"),
                                     test::MakePhoneme(0.58, 0.20, "_:")};
  CharacterParams params;
  params.gaze.enabled = false;
  // At the middle of the first vowel: aa on its own.
  const auto speak = [&](const Rig& rig) {
    const CharacterRig character_rig = CharacterRig::Build(rig);
    Character character(character_rig, params);
    REQUIRE(character.Speak(line, Seconds(0.0)) == CharacterError::kNone);
    REQUIRE(character.Update(Seconds(0.2)) == CharacterError::kNone);
    return std::pair(character_rig.visemes().style(),
                     std::vector<float>(character.weights().begin(), character.weights().end()));
  };
  const auto [baked_style, baked] = speak(named);
  CHECK(baked_style == VisemeMappingStyle::kPerViseme);
  CHECK(baked[*named.FindShape("viseme_aa")] > 0.3f);
  CHECK(baked[*named.FindShape("jawOpen")] == 0.0f);  // the baked target carries the jaw

  const auto [mapped_style, mapped] = speak(head);
  CHECK(mapped_style == VisemeMappingStyle::kArkit);
  CHECK(mapped[*head.FindShape("jawOpen")] > 0.1f);

  // The same face either way (within the clamping both do per shape).
  CHECK(MaxDistance(Blend(named, baked), Blend(head, mapped)) < 0.02f);
}

TEST_CASE("Standard shapes: GLB and .frig carry the names and visemes, and the GLB is validator-clean",
          "[standard_shapes][default_head]") {
  const std::filesystem::path folder = test::FreshOutputFolder("standard_shapes");
  for (const ShapeNaming naming : {ShapeNaming::kArkit, ShapeNaming::kIct, ShapeNaming::kKeep}) {
    const Rig named = StandardizeShapes(test::DefaultHead(), {naming, VisemeTargets::kOculus}).rig;
    const std::filesystem::path glb = folder / (std::string(ToString(naming)) + ".glb");
    const std::filesystem::path frig = folder / (std::string(ToString(naming)) + ".frig");
    SaveRig(glb, named);
    SaveRig(frig, named);
    for (const std::filesystem::path& path : {glb, frig}) {
      INFO(path);
      const Rig loaded = LoadRig(path);
      REQUIRE(loaded.shape_count() == named.shape_count());
      for (std::size_t s = 0; s < named.shape_count(); ++s) CHECK(loaded.shape_name(s) == named.shape_name(s));
    }
    if (naming == ShapeNaming::kArkit) test::RequireValidatorAccepts(glb);
  }
}

TEST_CASE("Standard shapes: a clash keeps the second shape's own name, and a rig without mouth shapes keeps its "
          "viseme targets", "[standard_shapes]") {
  const Rig both = test::MakeNamedGridRig({"eyeBlink_L", "eyeBlinkLeft", "jawOpen"});
  const StandardShapesResult named = StandardizeShapes(both);
  CHECK(ShapeNames(named.rig).contains("eyeBlink_L"));
  CHECK(ShapeNames(named.rig).contains("eyeBlinkLeft"));
  CHECK(std::any_of(named.report.warnings.begin(), named.report.warnings.end(), [](const std::string& warning) {
    return warning.find("eyeBlink_L keeps its name") != std::string::npos;
  }));

  const Rig visemes_only = test::MakeNamedGridRig({"PP", "aa", "ou"});
  const StandardShapesResult kept = StandardizeShapes(visemes_only);
  CHECK(ShapeNames(kept.rig) == std::set<std::string>{"viseme_PP", "viseme_aa", "viseme_U"});
  CHECK(kept.report.visemes_baked == 0);
  CHECK(kept.report.viseme_targets == 3);

  std::size_t removed = 0;
  const Rig baked = StandardizeShapes(test::MakeNamedGridRig({"jawOpen", "mouthFunnel", "viseme_aa"})).rig;
  CHECK(WithoutBakedVisemes(baked, &removed).shape_count() == 2);
  CHECK(removed == 15);
  CHECK(WithoutBakedVisemes(visemes_only, &removed).shape_count() == 3);
  CHECK(removed == 0);
}

}  // namespace facerig
