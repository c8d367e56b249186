// A photograph projected onto a fitted face's UVs: the skin texture of a head
// made from one photo.
//
// The mesh is the fitted face in its own frame (+Y up, the face looking along
// +Z, the character's left at +X, as the built-in head and ICT-FaceKit); the
// camera is one under which Rasterize(mesh, camera) overlays the mesh on the
// photo. Every texel of the skin parts' UV space (parts whose RoleOfPart is
// kSkin) takes, in this order of preference:
//   1. the photo at its surface point, where the z-buffer sees that point,
//      weighted by how squarely the surface faces the camera (fading to 0 at
//      grazing angles) and by the skin mask there (PhotoSkinMask: no
//      background, hair or teeth), or on the scalp and above the brows by the
//      head mask (PhotoHair: the photo's hair, still no background);
//   2. the photo at its mirror point (the same barycentrics on the mirror
//      partners of its triangle's vertices, across the face's symmetry plane),
//      where the photo sees that side instead, scaled per side and channel so
//      that texels seen both ways agree (one side is often lit more);
//   3. what remains: on the scalp the photo's hair colour (with the
//      template's painted strands as detail, if it has any); elsewhere the
//      seen colours diffused outwards (push-pull), turning into a skin colour
//      estimated from the cheeks over `fill_radius` texels.
// Each layer is blended over the next by its weight, so seams stay soft.
// With the photo's fitted lighting (PhotoLighting) each photo colour is first
// divided by that light's shading at its surface normal relative to the
// median shading of the squarely seen skin (clamped, and so that no channel
// clips): the player lights the head again, so the photo's own light (one
// cheek brighter, the jaw's shadow) should not be baked in. The skin colour
// and the tilt shading of the fill are then estimated from de-lit colours.
// Eyes, teeth, gums, tongue, mouth interior, lashes and eye layers take no
// photo pixels and keep their own materials.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/offline/photo/hair.h"
#include "facerig/offline/photo/skin_mask.h"
#include "facerig/offline/render/rasterizer.h"
#include "facerig/runtime/material.h"
#include "facerig/runtime/mesh.h"

namespace facerig {

struct PhotoTextureParams {
  // Texels a side. At 1024 the face's UV island (ICT-FaceKit's, the built-in
  // head's) is about as many texels across as a 1024-pixel portrait shows the
  // face in pixels: more adds no detail, less loses some.
  int size = 1024;
  // Cosine between the surface normal and the direction to the camera at
  // which the photo starts to count, and from which it counts fully.
  float grazing_cos = 0.15f;
  float full_cos = 0.5f;
  // A point is seen when it lies no deeper than the z-buffer plus this many
  // photo pixels (in world units; more on surfaces seen at a slant).
  float depth_tolerance_pixels = 1.5f;
  // Texels over which seen colours fade into the estimated skin colour.
  float fill_radius = 48.0f;
  int png_compression = 3;  // 0-9: zlib level of the encoded texture
  // Take the photo's fitted light out of its colours (with a PhotoLighting).
  bool delight = true;
  // De-lighting: normals nearer the image plane than this are shaded as if
  // at this facing (the lighting was fitted on normals facing the camera),
  // and the factor a colour is divided by (its shade over the median's) is
  // clamped to [least, most].
  float delight_min_facing = 0.3f;
  float delight_least = 0.75f, delight_most = 1.6f;
};

// The photo's light to take out of the texture.
struct PhotoLighting {
  std::vector<glm::vec3> coefficients;  // PhotoFit::lighting; empty: no de-lighting
  glm::mat3 rotation{1.0f};  // world to camera space (ScaledOrthoCamera::rotation)
};

// What a bake measured: fractions of the skin parts' texels.
struct PhotoTextureStats {
  double seen_fraction = 0.0;      // with a direct photo weight > 0
  double mirrored_fraction = 0.0;  // not fully seen, with a mirror weight > 0
  double filled_fraction = 0.0;    // neither: diffusion and skin colour only
  std::size_t mirror_pairs = 0;    // skin vertices with a mirror partner
  double mirror_partner_error = 0.0;  // mean distance (mesh units) from a reflected vertex to its partner
  // The scalp's hairline at the front, eye spacings above the eyes (0 without
  // a scalp), and how many of its 14 azimuth bins (10 degrees each, round the
  // front) the photo's forehead/hair boundary placed (the rest: a rule from
  // the eye spacing).
  double hairline_front = 0.0;
  int hairline_bins_from_photo = 0;
  // Wall-clock seconds of the steps: mirror partners, z-buffer and texel walk,
  // skin colour and fill, PNG encoding.
  double partner_seconds = 0.0, project_seconds = 0.0, fill_seconds = 0.0, encode_seconds = 0.0;
};

// A skin UV tile beyond the main one (UDIM layouts: ICT-FaceKit's back of
// the head lies at u in [1, 2]), baked into a texture of its own at half size.
struct PhotoTextureTile {
  glm::ivec2 tile{0};  // the UVs' integer part
  RgbImage texture;
  EncodedImage image;  // "photo_skin_<u>_<v>.png"
};

struct PhotoTexture {
  // size x size, sRGB, row 0 at the top (v = 1, OBJ's convention); every
  // texel set, also outside the skin's UV islands (so filtering across a
  // seam does not bring in a background).
  RgbImage texture;
  // Per texel, row-major: the direct photo weight and the mirror point's
  // photo weight in [0, 1] (0 outside the skin's UV islands); the mirror
  // counts for what the direct weight leaves.
  std::vector<float> direct_weight;
  std::vector<float> mirror_weight;
  // For looking at: red = direct weight, green = mirror weight, blue = the
  // skin's UV islands.
  RgbImage coverage;
  glm::vec3 skin_colour{0.0f};  // sRGB in [0, 1], estimated from the photo
  // The UV tile `texture` covers (the one with the most skin triangles), and the others.
  glm::ivec2 main_tile{0};
  std::vector<PhotoTextureTile> other_tiles;
  EncodedImage image;           // the texture as PNG, "photo_skin.png"
  Material material;            // white, textured by `image` (index set by ApplyPhotoTexture)
  PhotoTextureStats stats;
};

// \pre mesh.Validate(), corner UVs, the camera valid for Rasterize, the photo
// width x height x 3 bytes and the same size as the camera's image.
// \throw InvalidInputError naming the mesh, camera, photo or parameter at fault.
// `mask`: empty, or of the photo (BuildPhotoSkinMask). `hair`: when found,
// the scalp (the surface above a hairline set from the eyes: high on the
// forehead, over the ears, down to the nape) takes the photo's head pixels
// where the photo sees it above the brows, and elsewhere the hair's colour
// with a little low-frequency variation, where skin would be filled in.
PhotoTexture BakePhotoTexture(const Mesh& mesh, const RasterView& camera, const RgbImage& photo,
                              const PhotoTextureParams& params = {}, const PhotoSkinMask& mask = {},
                              const PhotoHair& hair = {}, const PhotoLighting& lighting = {});

// Gives every triangle of a skin part the baked material (its image appended
// to mesh.images; a skin triangle in another UV tile that tile's own
// material, "photo_skin_<u>_<v>"); other parts keep their materials (a mesh without any gets
// each part its RoleMaterial); materials and images nothing uses any more are
// dropped.
void ApplyPhotoTexture(Mesh& mesh, const PhotoTexture& texture);

}  // namespace facerig
