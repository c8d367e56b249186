#include "face_materials.h"

#include "facerig/runtime/part_roles.h"

#include <algorithm>
#include <cmath>
#include <cctype>
#include <string>

namespace facerig::player {

glm::vec3 BaseColor(Material material) {
  switch (material) {
    // Linear colours (the shader encodes sRGB).
    case Material::kSkin: return {0.54f, 0.33f, 0.245f};
    case Material::kSclera: return {0.72f, 0.69f, 0.66f};
    case Material::kIris: return {0.07f, 0.17f, 0.26f};
    case Material::kPupil: return {0.008f, 0.008f, 0.01f};
    case Material::kTeeth: return {0.66f, 0.62f, 0.52f};
    case Material::kGums: return {0.42f, 0.09f, 0.09f};
    case Material::kTongue: return {0.45f, 0.11f, 0.12f};
    case Material::kMouthInner: return {0.10f, 0.02f, 0.02f};
    case Material::kHidden: break;
  }
  return {0.0f, 0.0f, 0.0f};
}

Shading ShadingFor(Material kind) {
  switch (kind) {
    case Material::kSkin: return {{0.55f, 0.25f, 0.18f}, 24.0f, 0.05f, 0.35f, 1.0f};
    case Material::kSclera:
    case Material::kIris: return {glm::vec3(0.15f), 500.0f, 0.9f, 0.0f, 1.0f};
    case Material::kPupil: return {glm::vec3(0.0f), 400.0f, 0.8f, 0.0f, 1.0f};
    case Material::kTeeth: return {{0.3f, 0.28f, 0.25f}, 60.0f, 0.15f, 0.0f, 0.7f};
    case Material::kGums:
    case Material::kTongue: return {{0.5f, 0.25f, 0.2f}, 40.0f, 0.12f, 0.0f, 0.5f};
    case Material::kMouthInner: return {glm::vec3(0.0f), 16.0f, 0.02f, 0.0f, 0.3f};
    case Material::kHidden: break;
  }
  return {};
}

float ShininessForRoughness(float roughness) {
  const float alpha = std::max(roughness * roughness, 0.03f);
  return std::clamp(2.0f / (alpha * alpha) - 2.0f, 1.0f, 2048.0f);
}

namespace {

PartLook NamedPartLook(Material kind) {
  PartLook look;
  look.kind = kind;
  look.shading = ShadingFor(kind);
  look.base_colour = glm::vec4(BaseColor(kind), 1.0f);
  look.visible = kind != Material::kHidden;
  return look;
}

}  // namespace

Material MaterialForPart(std::string_view part_name) {
  switch (RoleOfPart(part_name)) {
    case PartRole::kSkin: return Material::kSkin;
    case PartRole::kSclera: return Material::kSclera;
    case PartRole::kIris: return Material::kIris;
    case PartRole::kPupil: return Material::kPupil;
    case PartRole::kTeeth: return Material::kTeeth;
    case PartRole::kGums: return Material::kGums;
    case PartRole::kTongue: return Material::kTongue;
    case PartRole::kMouthInner: return Material::kMouthInner;
    // Transparent layers and lash cards: drawn opaque without their material
    // they cover the eyes with grey shells or a black band.
    case PartRole::kEyeLayer:
    case PartRole::kLashes: return Material::kHidden;
  }
  return Material::kSkin;
}

PartLook LookForPart(const Rig& rig, const Part& part) {
  const Material kind = MaterialForPart(part.name);
  if (part.material < 0 || static_cast<std::size_t>(part.material) >= rig.materials().size()) {
    return NamedPartLook(kind);
  }
  const facerig::Material& material = rig.materials()[static_cast<std::size_t>(part.material)];
  if (IsPlaceholderMaterial(material)) return NamedPartLook(kind);
  PartLook look;
  look.from_material = true;
  look.kind = kind == Material::kHidden ? Material::kSkin : kind;
  look.shading = ShadingFor(look.kind);
  // The material's roughness replaces the named kind's gloss; its wrap and
  // ambient (skin scattering, a dark mouth) stay.
  look.shading.shininess = ShininessForRoughness(material.roughness);
  look.shading.specular = 0.04f;  // dielectric reflectance at normal incidence
  look.base_colour = material.base_colour;
  look.base_colour_image = material.base_colour_image;
  look.normal_image = material.normal_image;
  look.alpha_mode = material.alpha_mode;
  look.alpha_cutoff = material.alpha_cutoff;
  look.double_sided = material.double_sided;
  look.visible = kind != Material::kHidden || material.alpha_mode != AlphaMode::kOpaque;
  return look;
}

const char* ToString(Material material) {
  switch (material) {
    case Material::kSkin: return "skin";
    case Material::kSclera: return "sclera";
    case Material::kIris: return "iris";
    case Material::kPupil: return "pupil";
    case Material::kTeeth: return "teeth";
    case Material::kGums: return "gums";
    case Material::kTongue: return "tongue";
    case Material::kMouthInner: return "mouth inner";
    case Material::kHidden: return "hidden";
  }
  return "?";
}

}  // namespace facerig::player
