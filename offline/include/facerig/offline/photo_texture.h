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
//      grazing angles);
//   2. the photo at its mirror point (the same barycentrics on the mirror
//      partners of its triangle's vertices, across the face's symmetry plane),
//      where the photo sees that side instead, scaled per side and channel so
//      that texels seen both ways agree (one side is often lit more);
//   3. what remains: the seen colours diffused outwards (push-pull), turning
//      into a skin colour estimated from the cheeks over `fill_radius` texels.
// Each layer is blended over the next by its weight, so seams stay soft.
// Eyes, teeth, gums, tongue, mouth interior, lashes and eye layers take no
// photo pixels and keep their own materials.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/offline/rasterizer.h"
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
};

// What a bake measured: fractions of the skin parts' texels.
struct PhotoTextureStats {
  double seen_fraction = 0.0;      // with a direct photo weight > 0
  double mirrored_fraction = 0.0;  // not fully seen, with a mirror weight > 0
  double filled_fraction = 0.0;    // neither: diffusion and skin colour only
  std::size_t mirror_pairs = 0;    // skin vertices with a mirror partner
  double mirror_partner_error = 0.0;  // mean distance (mesh units) from a reflected vertex to its partner
  // Wall-clock seconds of the steps: mirror partners, z-buffer and texel walk,
  // skin colour and fill, PNG encoding.
  double partner_seconds = 0.0, project_seconds = 0.0, fill_seconds = 0.0, encode_seconds = 0.0;
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
  EncodedImage image;           // the texture as PNG, "photo_skin.png"
  Material material;            // white, textured by `image` (index set by ApplyPhotoTexture)
  PhotoTextureStats stats;
};

// \pre mesh.Validate(), corner UVs, the camera valid for Rasterize, the photo
// width x height x 3 bytes and the same size as the camera's image.
// \throw InvalidInputError naming the mesh, camera, photo or parameter at fault.
PhotoTexture BakePhotoTexture(const Mesh& mesh, const RasterView& camera, const RgbImage& photo,
                              const PhotoTextureParams& params = {});

// Gives every triangle of a skin part the baked material (its image appended
// to mesh.images); other parts keep their materials (a mesh without any gets
// each part its RoleMaterial); materials and images nothing uses any more are
// dropped.
void ApplyPhotoTexture(Mesh& mesh, const PhotoTexture& texture);

}  // namespace facerig
