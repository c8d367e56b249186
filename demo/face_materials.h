// How each rig part is drawn: the rig's own material when the part has one,
// else a colour chosen by the part's name (MaterialForPart and ToString are
// declared in face_renderer.h).
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "face_renderer.h"
#include "facerig/runtime/material.h"

namespace facerig::player {

// Linear RGB of a named part; black for kHidden.
glm::vec3 BaseColor(Material material);

// The lighting response of a surface (the face shader's inputs besides colour).
struct Shading {
  glm::vec3 wrap{0.0f};         // per-channel wrap of the diffuse term: red > blue reads as subsurface scattering
  float shininess = 16.0f;      // normalised Blinn-Phong exponent
  float specular = 0.04f;       // specular strength at normal incidence
  float rim = 0.0f;             // back-light rim strength
  float ambient = 1.0f;         // ambient scale (< 1 inside the mouth: occluded)
};
// The shading of a named part kind (skin, eyes, mouth ...).
Shading ShadingFor(Material kind);
// The Blinn-Phong exponent whose lobe matches GGX at `roughness` (alpha = roughness^2).
float ShininessForRoughness(float roughness);

// Everything the renderer needs to draw one part.
struct PartLook {
  Material kind = Material::kSkin;  // from the name: skin wrap, eye details, mouth ambient
  Shading shading;
  glm::vec4 base_colour{1.0f};      // linear RGBA
  std::int32_t base_colour_image = -1, normal_image = -1;  // indices into Rig::images()
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha_cutoff = 0.5f;
  bool double_sided = true;         // named parts: the mouth interior is seen from both sides
  bool from_material = false;       // the rig's material, not the named-part colour
  bool visible = true;
};

// The part's material (rig.materials()[part.material]) unless it is a
// placeholder (opaque, untextured, grey or white: an OBJ's bare usemtl, an
// exporter's default), else its named-part look. ICT's overlays and lashes stay hidden unless their
// material blends or masks: drawn opaque they would cover the eyes.
PartLook LookForPart(const Rig& rig, const Part& part);

}  // namespace facerig::player
