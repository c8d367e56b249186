// What the lid choice judges a build by (the blinks' worst edge stretch) and
// the landmarks it builds the second time with. The choice between two real
// builds is tested on decimated ICT faces (rig_build_decimated_test.cpp).
#include "facerig/offline/rigging/lid_choice.h"

#include <catch2/catch.hpp>

namespace facerig {
namespace {

// One unit right triangle (edges 1, 1, sqrt 2) and a shape moving vertex 1 by `delta`.
RawRig Triangle1(const std::string& shape_name, glm::vec3 delta) {
  RawRig rig;
  rig.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  rig.triangles = {{0, 1, 2}};
  rig.shapes.push_back({.name = shape_name, .vertex_indices = {1}, .position_deltas = {delta}, .normal_deltas = {}});
  return rig;
}

}  // namespace

TEST_CASE("Lid choice: a build is judged by its blink shapes' worst edge stretch, in any spelling", "[lids]") {
  // Vertex 1 moved to (3, 0, 0): edge 0-1 from 1 to 3.
  CHECK(WorstBlinkStretch(Triangle1("eyeBlink_L", {2, 0, 0})).value() == Approx(3.0f));
  CHECK(WorstBlinkStretch(Triangle1("EyeBlinkRight", {2, 0, 0})).value() == Approx(3.0f));
  // Shortened edges do not count: at least 1.
  CHECK(WorstBlinkStretch(Triangle1("eyeBlinkLeft", {-0.5f, 0, 0})).value() == Approx(1.0f));
  // Other shapes are not blinks; a rig without blinks cannot be judged.
  CHECK_FALSE(WorstBlinkStretch(Triangle1("jawOpen", {2, 0, 0})).has_value());

  RawRig both = Triangle1("eyeBlink_L", {1, 0, 0});
  both.shapes.push_back({.name = "eyeBlink_R", .vertex_indices = {1}, .position_deltas = {{3, 0, 0}}, .normal_deltas = {}});
  both.shapes.push_back({.name = "jawOpen", .vertex_indices = {1}, .position_deltas = {{9, 0, 0}}, .normal_deltas = {}});
  CHECK(WorstBlinkStretch(both).value() == Approx(4.0f));  // the worse blink; jawOpen's 10x ignored
}

TEST_CASE("Lid choice: trusting the doubtful lid points puts back their detected confidence, nothing else",
          "[lids]") {
  FaceLandmarks detected;
  for (std::uint32_t k = 0; k < 68; ++k) {
    detected.points.push_back({static_cast<float>(k), 0, 0});
    detected.indices.push_back(k);
    detected.confidence.push_back(k == 40 || k == 47 ? 0.0f : 0.9f);
  }
  DoubtfulLidPoints doubtful;
  doubtful.points[40] = doubtful.points[47] = true;
  doubtful.confidence.assign(68, 0.0f);
  doubtful.confidence[40] = 0.8f;
  doubtful.confidence[47] = 0.7f;
  const FaceLandmarks trusting = TrustingDoubtfulLids(detected, doubtful);
  CHECK(trusting.confidence[40] == 0.8f);
  CHECK(trusting.confidence[47] == 0.7f);
  CHECK(trusting.confidence[41] == 0.9f);
  CHECK(trusting.points == detected.points);
  CHECK(IndicesOf(doubtful.points) == std::vector<std::uint32_t>{40, 47});

  // A file's subset of points is matched by index, not by position in the list.
  FaceLandmarks subset{.points = {{0, 0, 0}, {1, 0, 0}}, .confidence = {0.0f, 0.5f}, .indices = {47, 30}};
  const FaceLandmarks trusting_subset = TrustingDoubtfulLids(subset, doubtful);
  CHECK(trusting_subset.confidence == std::vector<float>{0.7f, 0.5f});
}

}  // namespace facerig
