#include "face_materials.h"

#include <cctype>
#include <string>

namespace facerig::player {

glm::vec3 BaseColor(Material material) {
  switch (material) {
    // Linear colours (the shader outputs gamma 2.2).
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

namespace {

std::string Lower(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

}  // namespace

Material MaterialForPart(std::string_view part_name) {
  const std::string name = Lower(part_name);
  const auto has = [&](const char* word) { return name.find(word) != std::string::npos; };
  if (has("occlusion") || has("lacrimal") || has("eyeblend")) return Material::kHidden;
  if (has("lash")) return Material::kHidden;
  if (has("sclera") || has("eye_white") || has("eyewhite")) return Material::kSclera;
  if (has("pupil")) return Material::kPupil;
  if (has("iris")) return Material::kIris;
  if (has("teeth") || has("tooth")) return Material::kTeeth;
  if (has("gum")) return Material::kGums;
  if (has("tongue")) return Material::kTongue;
  if (has("mouth_inner") || has("mouthinner") || has("mouth_cavity")) return Material::kMouthInner;
  return Material::kSkin;
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
