// The steps of BakePhotoTexture (photo_texture.h), shared by its files.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/offline/photo_texture.h"

namespace facerig::photo_texture {

// Per texel of the texture being baked, row-major; colours sRGB in [0, 1].
struct TexelLayers {
  int size = 0;
  std::vector<glm::vec3> direct_colour, mirror_colour;
  std::vector<float> direct_weight, mirror_weight;
  std::vector<std::uint8_t> skin;   // 1: inside a skin triangle's UVs
  std::vector<std::uint8_t> cheek;  // 1: its surface point lies on a cheek
  std::vector<std::uint8_t> side;   // 1: its surface point lies behind the symmetry plane
};

// Each vertex's mirror partner across the face's symmetry plane (-1: none);
// only vertices of skin triangles are paired.
struct MirrorPartners {
  std::vector<std::int32_t> partner;
  glm::vec3 plane_normal{1.0f, 0.0f, 0.0f};  // the symmetry plane: dot(normal, p) = offset
  float plane_offset = 0.0f;
  std::size_t pairs = 0;
  double mean_error = 0.0;  // |reflected vertex - its partner|, mesh units
};
MirrorPartners FindMirrorPartners(const Mesh& mesh, const std::vector<std::uint8_t>& skin_vertex);

// Balls round the cheeks, below and beside the eyes (none without eye parts).
struct CheekRegion {
  bool found = false;
  std::array<glm::vec3, 2> centres{};
  float radius = 0.0f;
  bool Contains(const glm::vec3& p) const;
};
CheekRegion FindCheeks(const Mesh& mesh);

// Fills the layers' direct and mirror samples from the photo for every texel
// of the skin triangles, each photo pixel weighted by the mask.
void ProjectPhoto(const Mesh& mesh, const std::vector<std::uint8_t>& skin_triangle, const RasterView& camera,
                  const RgbImage& photo, const PhotoSkinMask& mask, const MirrorPartners& mirror,
                  const CheekRegion& cheeks, const PhotoTextureParams& params, TexelLayers& layers);

// Scales each side's mirror colours so that, where a texel is seen both
// directly and in its mirror, the two agree on average: one side of a face
// is often lit more than the other.
void BalanceMirrorLight(TexelLayers& layers);

// Median colour of the squarely seen cheek texels (else of all squarely seen
// skin texels; else RoleMaterial's skin), sRGB in [0, 1].
glm::vec3 EstimateSkinColour(const TexelLayers& layers);

// Every texel's colour: direct over mirror over the push-pull diffusion of
// both, which fades into `skin_colour` over `fill_radius` texels.
std::vector<glm::vec3> FillTexels(const TexelLayers& layers, const glm::vec3& skin_colour, float fill_radius);

}  // namespace facerig::photo_texture
