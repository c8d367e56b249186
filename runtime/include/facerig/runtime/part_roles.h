// What a part of a face is, from its name: the built-in head's names ("skin",
// "eye_white_L", "iris_R", ...), ICT-FaceKit's ("M_Face", "M_ScleraLeft",
// "M_EyeOcclusion", ...) and the usual words of other assets. Renderers pick a
// look by it; builds give a part whose material is only a placeholder a
// material of its role.
#pragma once

#include <cstdint>
#include <string_view>

#include "facerig/runtime/material.h"
#include "facerig/runtime/mesh.h"

namespace facerig {

enum class PartRole : std::uint8_t {
  kSkin = 0,  // also every name not recognised
  kSclera,
  kIris,
  kPupil,
  kTeeth,
  kGums,
  kTongue,
  kMouthInner,
  kEyeLayer,  // thin transparent layers over the eye: occlusion shadow, tear film, lid blend
  kLashes,
};

PartRole RoleOfPart(std::string_view part_name);
const char* ToString(PartRole role);

// Opaque, untextured, grey or white: an OBJ's bare usemtl, glTF's default
// material, an exporter's default grey, ICT-FaceKit's Kd 0.6 on every part.
// It says nothing about the part; its name says more.
bool IsPlaceholderMaterial(const Material& material);

// A material for a part of this role (linear colours; layers and lashes
// alpha-blended so that they never cover the eyes), named after the role.
Material RoleMaterial(PartRole role);

// Every triangle whose material is a placeholder, or that has none, takes its
// part's RoleMaterial (added once per role); other materials stay as they are.
void ReplacePlaceholderMaterials(Mesh& mesh);

}  // namespace facerig
