#include "facerig/runtime/ascii_case.h"
#include "facerig/runtime/part_roles.h"

#include <map>
#include <utility>
#include <cctype>
#include <cmath>
#include <string>

#include <glm/vec3.hpp>

namespace facerig {
namespace {

Material Opaque(PartRole role, glm::vec3 colour, float roughness) {
  return Material{.name = ToString(role), .base_colour = glm::vec4(colour, 1.0f), .roughness = roughness};
}

Material Blended(PartRole role, glm::vec3 colour, float alpha, float roughness) {
  return Material{.name = ToString(role),
                  .base_colour = glm::vec4(colour, alpha),
                  .alpha_mode = AlphaMode::kBlend,
                  .double_sided = true,
                  .roughness = roughness};
}

}  // namespace

PartRole RoleOfPart(std::string_view part_name) {
  const std::string name = LowerAscii(part_name);
  const auto has = [&](const char* word) { return name.find(word) != std::string::npos; };
  if (has("occlusion") || has("lacrimal") || has("eyeblend") || has("eye_blend") || has("tear")) {
    return PartRole::kEyeLayer;
  }
  if (has("lash")) return PartRole::kLashes;
  if (has("sclera") || has("eye_white") || has("eyewhite")) return PartRole::kSclera;
  if (has("pupil")) return PartRole::kPupil;
  if (has("iris")) return PartRole::kIris;
  if (has("teeth") || has("tooth")) return PartRole::kTeeth;
  if (has("gum")) return PartRole::kGums;
  if (has("tongue")) return PartRole::kTongue;
  if (has("mouth_inner") || has("mouthinner") || has("mouth_cavity")) return PartRole::kMouthInner;
  return PartRole::kSkin;
}

const char* ToString(PartRole role) {
  switch (role) {
    case PartRole::kSkin: return "skin";
    case PartRole::kSclera: return "sclera";
    case PartRole::kIris: return "iris";
    case PartRole::kPupil: return "pupil";
    case PartRole::kTeeth: return "teeth";
    case PartRole::kGums: return "gums";
    case PartRole::kTongue: return "tongue";
    case PartRole::kMouthInner: return "mouth_inner";
    case PartRole::kEyeLayer: return "eye_layer";
    case PartRole::kLashes: return "lashes";
  }
  return "skin";
}

bool IsPlaceholderMaterial(const Material& material) {
  const glm::vec4& c = material.base_colour;
  const bool grey = std::abs(c.r - c.g) < 0.02f && std::abs(c.g - c.b) < 0.02f && c.a == 1.0f;
  return grey && material.base_colour_image < 0 && material.normal_image < 0 &&
         material.alpha_mode == AlphaMode::kOpaque;
}

Material RoleMaterial(PartRole role) {
  switch (role) {
    case PartRole::kSkin: return Opaque(role, {0.54f, 0.33f, 0.245f}, 0.6f);
    case PartRole::kSclera: return Opaque(role, {0.80f, 0.76f, 0.72f}, 0.15f);
    case PartRole::kIris: return Opaque(role, {0.07f, 0.17f, 0.26f}, 0.15f);
    case PartRole::kPupil: return Opaque(role, {0.008f, 0.008f, 0.01f}, 0.15f);
    case PartRole::kTeeth: return Opaque(role, {0.80f, 0.76f, 0.66f}, 0.35f);
    case PartRole::kGums: return Opaque(role, {0.42f, 0.09f, 0.09f}, 0.45f);
    case PartRole::kTongue: return Opaque(role, {0.45f, 0.11f, 0.12f}, 0.45f);
    case PartRole::kMouthInner: return Opaque(role, {0.10f, 0.02f, 0.02f}, 0.7f);
    // A faint shadow and sheen: drawn opaque these layers are grey shells over the eyes.
    case PartRole::kEyeLayer: return Blended(role, {0.12f, 0.07f, 0.06f}, 0.2f, 0.1f);
    case PartRole::kLashes: return Blended(role, {0.02f, 0.015f, 0.01f}, 0.3f, 0.7f);
  }
  return Opaque(PartRole::kSkin, {0.54f, 0.33f, 0.245f}, 0.6f);
}

void ReplacePlaceholderMaterials(Mesh& mesh) {
  // One replacement per (placeholder or none, role), keeping the placeholder's name.
  std::map<std::pair<std::int64_t, PartRole>, std::uint32_t> replacement;
  const bool had_materials = !mesh.triangle_materials.empty();
  std::vector<std::uint32_t> materials(mesh.triangle_count());
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const std::int64_t old = had_materials ? std::int64_t{mesh.triangle_materials[t]} : -1;
    if (old >= 0 && !IsPlaceholderMaterial(mesh.materials[static_cast<std::size_t>(old)])) {
      materials[t] = static_cast<std::uint32_t>(old);
      continue;
    }
    const std::string_view part = mesh.triangle_parts.empty() ? std::string_view() : mesh.part_names[mesh.triangle_parts[t]];
    const PartRole role = RoleOfPart(part);
    const auto [it, added] = replacement.try_emplace({old, role}, static_cast<std::uint32_t>(mesh.materials.size()));
    if (added) {
      Material material = RoleMaterial(role);
      if (old >= 0) material.name = mesh.materials[static_cast<std::size_t>(old)].name;
      mesh.materials.push_back(std::move(material));
    }
    materials[t] = it->second;
  }
  // The placeholders no triangle uses any more are dropped.
  std::vector<std::int64_t> kept_as(mesh.materials.size(), -1);
  std::vector<Material> kept;
  for (std::uint32_t& m : materials) {
    if (kept_as[m] < 0) {
      kept_as[m] = static_cast<std::int64_t>(kept.size());
      kept.push_back(std::move(mesh.materials[m]));
    }
    m = static_cast<std::uint32_t>(kept_as[m]);
  }
  mesh.materials = std::move(kept);
  mesh.triangle_materials = std::move(materials);
}

}  // namespace facerig
