// The template rig on a photo's fitted face, wearing the photo.
#include "facerig/offline/photo/hair.h"
#include "facerig/offline/photo/skin_mask.h"
#include "facerig/offline/photo/rig.h"

#include <future>
#include <optional>
#include <string>
#include <utility>

#include "facerig/offline/error.h"
#include "facerig/offline/render/eye_textures.h"
#include "facerig/runtime/part_roles.h"
#include "facerig/runtime/rig_builder.h"
#include "facerig/runtime/rig_surface.h"
#include "facerig/runtime/shape_names.h"
#include "photo/fit/eye_fit.h"

namespace facerig {
namespace {

void CheckSizes(const Rig& rig, const Mesh& surface, const PhotoFit& fit) {
  const std::size_t n = rig.vertex_count();
  if (fit.rest_positions.size() != n || fit.posed_positions.size() != n) {
    throw InvalidInputError("photo rig: the fit has " + std::to_string(fit.rest_positions.size()) +
                                " vertices, the template " + std::to_string(n),
                            "fit");
  }
  if (surface.vertex_count() != n || surface.triangle_count() != rig.triangle_count()) {
    throw InvalidInputError("photo rig: the template's surface has " + std::to_string(surface.vertex_count()) +
                                " vertices and " + std::to_string(surface.triangle_count()) +
                                " triangles, the rig " + std::to_string(n) + " and " +
                                std::to_string(rig.triangle_count()),
                            "surface");
  }
  if (surface.corner_uvs.empty()) throw InvalidInputError("photo rig: the template has no UVs to bake into", "surface");
}

// The template with its neutral replaced; its shapes' deltas as they were.
Rig WithNeutral(const Rig& rig, const std::vector<glm::vec3>& neutral) {
  RawRig raw = RigBuilder::ToRaw(rig);
  raw.positions = neutral;
  raw.normals.clear();  // recomputed by the builder for the new face
  std::string problem;
  std::optional<Rig> built = RigBuilder::Build(std::move(raw), &problem);
  if (!built) throw InvalidInputError("photo rig: the fitted rig is invalid: " + problem, "fit");
  return std::move(*built);
}

}  // namespace

PhotoModelParams PhotoModelParamsFor(const Rig& rig) {
  const PhotoModelParams defaults;
  PhotoModelParams params;
  params.expressions.clear();
  for (const std::string& name : defaults.expressions) {
    const std::vector<std::size_t> found = FindShapesByArkitName(rig, name);
    if (found.size() == 1) params.expressions.emplace_back(rig.shape(found[0]).name);
  }
  return params;
}

PhotoRig MakePhotoRig(const Rig& template_rig, Mesh surface, const PhotoFit& fit, const RgbImage& photo,
                      std::span<const glm::vec2> landmarks, const PhotoRigParams& params) {
  CheckSizes(template_rig, surface, fit);
  surface.corner_normals.clear();  // the template's: not the fitted face's
  ReplacePlaceholderMaterials(surface);
  PhotoRig result;
  // The eyes are painted on the template's own surface, a copy, on another
  // core while the skin is baked: painting changes only materials and images,
  // which are taken back before the skin's are added.
  Mesh eyes = surface;
  std::future<std::size_t> eyes_painted = std::async(std::launch::async, [&eyes] { return PaintEyeTextures(eyes); });
  std::vector<glm::vec3> posed = fit.posed_positions, rest = fit.rest_positions;
  if (fit.deformed && landmarks.size() == 68) {
    const LidMarginFit lids = FitLidMarginsToPhoto(surface, landmarks, fit.landmark_vertices, fit.camera, photo.width,
                                                   photo.height, posed, rest);
    result.lid_margins_fitted = lids.margins;
  }
  surface.positions = posed;
  PhotoHair hair;
  if (!landmarks.empty()) {
    result.skin_mask = BuildPhotoSkinMask(photo, landmarks, params.mask);
    hair = FindPhotoHair(photo, landmarks, result.skin_mask, params.hair);
  }
  const PhotoLighting lighting{.coefficients = fit.lighting, .rotation = fit.camera.rotation};
  const PhotoTexture texture =
      BakePhotoTexture(surface, fit.view, photo, params.texture, result.skin_mask, hair, lighting);
  result.hair_found = hair.found;
  result.hair_colour = hair.colour;
  result.eye_materials_painted = eyes_painted.get();
  surface.materials = std::move(eyes.materials);
  surface.images = std::move(eyes.images);
  ApplyPhotoTexture(surface, texture);
  surface.positions = rest;
  std::string problem;
  std::optional<Rig> dressed = RigWithSurface(WithNeutral(template_rig, rest), surface, &problem);
  if (!dressed) throw InvalidInputError("photo rig: the template's surface does not fit its rig: " + problem, "surface");
  result.rig = std::move(*dressed);
  result.texture_stats = texture.stats;
  result.skin_colour = texture.skin_colour;
  return result;
}

}  // namespace facerig
