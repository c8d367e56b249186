#include "mouth_light.h"

#include <catch2/catch.hpp>

#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "facerig/runtime/rig_builder.h"

namespace facerig::player {
namespace {

// One triangle per part, facing the viewer (+Z) at depth z, 4 units wide.
void AddPart(RawRig& raw, const std::string& name, float z) {
  const auto first = static_cast<std::uint32_t>(raw.positions.size());
  raw.positions.insert(raw.positions.end(), {{-2.0f, 0.0f, z}, {2.0f, 0.0f, z}, {0.0f, 1.0f, z}});
  raw.parts.push_back({name, static_cast<std::uint32_t>(raw.triangles.size()), 1});
  raw.triangles.push_back({first, first + 1, first + 2});
}

}  // namespace

TEST_CASE("mouth light: the mouth's parts darken with depth behind their front, the rest stays lit",
          "[player]") {
  RawRig raw;
  AddPart(raw, "skin_face", 2.0f);
  AddPart(raw, "teeth", 1.0f);
  AddPart(raw, "tongue", 0.5f);
  AddPart(raw, "mouth_inner", -1.0f);
  raw.units = Units::kMetres;
  std::string problem;
  const std::optional<Rig> rig = RigBuilder::Build(raw, &problem);
  REQUIRE(rig.has_value());
  const std::vector<float> light = MouthLight(*rig, glm::mat4(1.0f));
  REQUIRE(light.size() == 12);
  CHECK(light[0] == 1.0f);       // skin, in front of everything
  CHECK(light[3] == 1.0f);       // the front of the teeth
  CHECK(light[6] < light[3]);    // the tongue, half a unit behind
  CHECK(light[6] > 0.3f);
  CHECK(light[9] < 0.1f);        // the back of the mouth: two units behind, half the width
  // Facing away (+Z flipped), the back becomes the front.
  const std::vector<float> turned = MouthLight(*rig, glm::scale(glm::mat4(1.0f), glm::vec3(1, 1, -1)));
  CHECK(turned[9] == 1.0f);
  CHECK(turned[3] < 0.1f);
}

TEST_CASE("mouth light: a rig without mouth parts is lit everywhere", "[player]") {
  RawRig raw;
  AddPart(raw, "skin", 0.0f);
  const std::optional<Rig> rig = RigBuilder::Build(raw);
  REQUIRE(rig.has_value());
  CHECK(MouthLight(*rig, glm::mat4(1.0f)) == std::vector<float>(3, 1.0f));
}

}  // namespace facerig::player
