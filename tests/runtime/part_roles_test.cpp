#include "facerig/runtime/part_roles.h"

#include <catch2/catch.hpp>

namespace facerig {

TEST_CASE("part roles: the built-in head's, ICT-FaceKit's and common names", "[part_roles]") {
  CHECK(RoleOfPart("skin") == PartRole::kSkin);
  CHECK(RoleOfPart("M_Face") == PartRole::kSkin);
  CHECK(RoleOfPart("Body_Mesh.001") == PartRole::kSkin);
  CHECK(RoleOfPart("eye_white_L") == PartRole::kSclera);
  CHECK(RoleOfPart("M_ScleraLeft") == PartRole::kSclera);
  CHECK(RoleOfPart("iris_R") == PartRole::kIris);
  CHECK(RoleOfPart("pupil_L") == PartRole::kPupil);
  CHECK(RoleOfPart("M_Teeth") == PartRole::kTeeth);
  CHECK(RoleOfPart("M_GumsTongue") == PartRole::kGums);
  CHECK(RoleOfPart("tongue") == PartRole::kTongue);
  CHECK(RoleOfPart("mouth_inner") == PartRole::kMouthInner);
  CHECK(RoleOfPart("M_EyeOcclusion") == PartRole::kEyeLayer);
  CHECK(RoleOfPart("M_LacrimalFluid") == PartRole::kEyeLayer);
  CHECK(RoleOfPart("M_EyeBlend") == PartRole::kEyeLayer);
  CHECK(RoleOfPart("M_EyeLashes") == PartRole::kLashes);
}

TEST_CASE("part roles: placeholders are opaque, untextured greys", "[part_roles]") {
  CHECK(IsPlaceholderMaterial(Material{.name = "bare"}));
  CHECK(IsPlaceholderMaterial(Material{.name = "ict", .base_colour = {0.6f, 0.6f, 0.6f, 1.0f}, .roughness = 0.3f}));
  CHECK_FALSE(IsPlaceholderMaterial(Material{.name = "red", .base_colour = {0.8f, 0.1f, 0.1f, 1.0f}}));
  CHECK_FALSE(IsPlaceholderMaterial(Material{.name = "textured", .base_colour_image = 0}));
  CHECK_FALSE(IsPlaceholderMaterial(Material{.name = "glass", .alpha_mode = AlphaMode::kBlend}));
  CHECK_FALSE(IsPlaceholderMaterial(Material{.name = "faded", .base_colour = {0.6f, 0.6f, 0.6f, 0.5f}}));
}

TEST_CASE("part roles: placeholder materials are replaced by their part's role, others kept", "[part_roles]") {
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 1, 2}, {0, 1, 2}, {0, 1, 2}};
  mesh.part_names = {"M_Face", "M_EyeLashes", "M_Teeth", "lips"};
  mesh.triangle_parts = {0, 1, 2, 3};
  mesh.materials = {Material{.name = "M_Face", .base_colour = {0.6f, 0.6f, 0.6f, 1.0f}},
                    Material{.name = "M_EyeLashes", .base_colour = {0.6f, 0.6f, 0.6f, 1.0f}},
                    Material{.name = "M_Teeth", .base_colour = {0.9f, 0.9f, 0.9f, 1.0f}},
                    Material{.name = "lipstick", .base_colour = {0.7f, 0.1f, 0.2f, 1.0f}}};
  mesh.triangle_materials = {0, 1, 2, 3};
  ReplacePlaceholderMaterials(mesh);
  REQUIRE(mesh.Validate());
  REQUIRE(mesh.materials.size() == 4);
  const auto material_of = [&](std::size_t t) { return mesh.materials[mesh.triangle_materials[t]]; };
  CHECK(material_of(0).name == "M_Face");  // the name stays, the colour is the role's
  CHECK(material_of(0).base_colour == RoleMaterial(PartRole::kSkin).base_colour);
  CHECK(material_of(1).alpha_mode == AlphaMode::kBlend);
  CHECK(material_of(1).base_colour.a < 1.0f);
  CHECK(material_of(2).base_colour == RoleMaterial(PartRole::kTeeth).base_colour);
  CHECK(material_of(3).name == "lipstick");
  CHECK(material_of(3).base_colour.r == Approx(0.7f));

  Mesh bare;  // no materials at all: one per role
  bare.positions = mesh.positions;
  bare.triangles = {{0, 1, 2}};
  ReplacePlaceholderMaterials(bare);
  REQUIRE(bare.materials.size() == 1);
  CHECK(bare.materials[0].name == "skin");
  CHECK(bare.triangle_materials == std::vector<std::uint32_t>{0});
}

}  // namespace facerig
