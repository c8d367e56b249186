// tongueOut made from ICT-FaceKit's tongue (its "gums_and_tongue" part; ICT
// has no such shape): the tip out past the lower front teeth, the skull
// still, and viseme TH putting the tip at the teeth.
#include "facerig/offline/rigging/tongue_out.h"

#include <algorithm>
#include <cstdio>
#include <limits>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/runtime/shape_names.h"
#include "facerig/runtime/speech/viseme_mapping.h"
#include "support/default_head_poses.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

struct Teeth {
  double lower_front = -std::numeric_limits<double>::infinity();  // along forward
  double lower_lingual = std::numeric_limits<double>::infinity();
  double lower_edge = -std::numeric_limits<double>::infinity();   // height
  double upper_front = -std::numeric_limits<double>::infinity();
  double upper_edge = std::numeric_limits<double>::infinity();
};

// ICT's front teeth in a pose: lower (carried by jawOpen) and upper, within
// 0.6 cm of the foremost tooth.
Teeth FrontTeeth(const Rig& rig, const FaceTemplateInfo& info, const std::vector<glm::vec3>& pose,
                 const SynthesisedTongueOut& tongue) {
  const TemplatePart* teeth = info.FindPart("teeth");
  REQUIRE(teeth);
  const std::vector<glm::vec3> jaw = test::Posed(rig, {{"jawOpen", 1.0f}});
  const auto lower = [&](std::uint32_t v) { return glm::length(jaw[v] - rig.positions()[v]) > 0.5f; };
  const glm::dvec3 forward(tongue.forward), up(tongue.up);
  Teeth result;
  for (std::uint32_t v = teeth->vertices.first; v <= teeth->vertices.last; ++v) {
    double& front = lower(v) ? result.lower_front : result.upper_front;
    front = std::max(front, glm::dot(glm::dvec3(pose[v]), forward));
  }
  for (std::uint32_t v = teeth->vertices.first; v <= teeth->vertices.last; ++v) {
    const double ahead = glm::dot(glm::dvec3(pose[v]), forward), height = glm::dot(glm::dvec3(pose[v]), up);
    if (lower(v) && ahead > result.lower_front - 0.6) {
      result.lower_lingual = std::min(result.lower_lingual, ahead);
      result.lower_edge = std::max(result.lower_edge, height);
    } else if (!lower(v) && ahead > result.upper_front - 0.6) {
      result.upper_edge = std::min(result.upper_edge, height);
    }
  }
  return result;
}

}  // namespace

TEST_CASE("(shared data) tongueOut made from ICT-FaceKit's tongue: the tip past the lower front teeth, the skull still",
          "[shared-data][tongue_out]") {
  const Rig& ict = test::IctRig();
  const FaceTemplateInfo info = ResolveFaceTemplateInfo(ict, test::IctDir());
  REQUIRE(FindShapesByArkitName(ict, "tongueOut").empty());
  SynthesisedTongueOut tongue;
  const std::optional<Rig> rig = WithSynthesisedTongueOut(ict, info, &tongue);
  REQUIRE(rig.has_value());
  CHECK(tongue.part == "gums_and_tongue");
  // The tongue's UV chart (451 vertices), not the gums or the floor of the mouth.
  CHECK(tongue.tongue_vertices > 400);
  CHECK(tongue.tongue_vertices < 500);
  CHECK(tongue.over_teeth);
  CHECK(tongue.forward.z > 0.99f);  // ICT faces +Z
  CHECK(tongue.up.y == 1.0f);

  const std::vector<glm::vec3> out = test::Posed(*rig, {{"tongueOut", 1.0f}});
  const Teeth teeth = FrontTeeth(*rig, info, out, tongue);
  const glm::dvec3 tip(out[tongue.tip_vertex]);
  const double tip_ahead = glm::dot(tip, glm::dvec3(tongue.forward));
  const double tip_height = glm::dot(tip, glm::dvec3(tongue.up));
  std::printf("ICT tongueOut: tongue %zu vertices, %.2f cm long; tip %.2f cm past the lower front teeth, %.2f cm "
              "above their edge\n",
              tongue.tongue_vertices, tongue.tongue_length, tip_ahead - teeth.lower_front,
              tip_height - teeth.lower_edge);
  CHECK(tip_ahead > teeth.lower_front + 1.0);
  CHECK(tip_height > teeth.lower_edge);

  // The skull stays: what jawOpen leaves still (upper teeth and gums, eyes,
  // the head) tongueOut leaves still too.
  const std::vector<glm::vec3> jaw = test::Posed(*rig, {{"jawOpen", 1.0f}});
  std::size_t still = 0, moved = 0;
  for (std::size_t v = 0; v < out.size(); ++v) {
    if (glm::length(jaw[v] - ict.positions()[v]) > 1e-6f) continue;
    ++still;
    if (glm::length(out[v] - ict.positions()[v]) > 1e-6f) ++moved;
  }
  CHECK(still > 8000);  // 8,507 of 26,719: ICT's jawOpen moves much of the face a little
  CHECK(moved == 0);
}

TEST_CASE("(shared data) viseme TH puts ICT-FaceKit's tongue tip at the teeth, DD behind them",
          "[shared-data][tongue_out]") {
  const Rig& ict = test::IctRig();
  SynthesisedTongueOut tongue;
  const FaceTemplateInfo info = ResolveFaceTemplateInfo(ict, test::IctDir());
  const std::optional<Rig> rig = WithSynthesisedTongueOut(ict, info, &tongue);
  REQUIRE(rig.has_value());
  const VisemeMappingResult mapping = BuildVisemeMapping(*rig);
  CHECK(mapping.warnings.empty());
  for (Viseme viseme : {Viseme::kTH, Viseme::kDD}) {
    std::vector<std::pair<std::string, float>> weights;
    for (const ShapeContribution& c : mapping.mapping.contributions(viseme)) {
      weights.emplace_back(std::string(rig->shape_name(c.shape)), c.weight);
    }
    const std::vector<glm::vec3> pose = test::Posed(*rig, weights);
    const Teeth teeth = FrontTeeth(*rig, info, pose, tongue);
    const glm::dvec3 tip(pose[tongue.tip_vertex]);
    const double ahead = glm::dot(tip, glm::dvec3(tongue.forward)), height = glm::dot(tip, glm::dvec3(tongue.up));
    std::printf("ICT viseme %s: tongue tip %.2f cm ahead of the lower front teeth's front (their lingual side %.2f, "
                "the upper ones' front %.2f), %.2f cm above their edge (the upper ones' edge %.2f)\n",
                std::string(ToString(viseme)).c_str(), ahead - teeth.lower_front, teeth.lower_lingual - teeth.lower_front,
                teeth.upper_front - teeth.lower_front, height - teeth.lower_edge, teeth.upper_edge - teeth.lower_edge);
    if (viseme == Viseme::kTH) {  // between the upper and lower front teeth, at the upper ones' front
      CHECK(ahead > teeth.lower_front);
      CHECK(ahead < teeth.upper_front + 0.3);
      CHECK(height > teeth.lower_edge - 0.15);
      CHECK(height < teeth.upper_edge);
    } else {  // at the lower front teeth's lingual side
      CHECK(ahead > teeth.lower_lingual - 0.3);
      CHECK(ahead < teeth.lower_front);
    }
  }
}

}  // namespace facerig
