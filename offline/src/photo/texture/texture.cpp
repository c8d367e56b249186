#include "facerig/offline/photo/texture.h"
#include "facerig/offline/render/png_encode.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>


#include "facerig/offline/error.h"
#include "facerig/runtime/part_roles.h"
#include "photo/texture/internal.h"
#include "render/unit_byte.h"

namespace facerig {
namespace {

using photo_texture::TexelLayers;

class Stopwatch {
 public:
  // Seconds since the last lap (or the start).
  double Lap() {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return seconds;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

void CheckInputs(const Mesh& mesh, const RasterView& camera, const RgbImage& photo, const PhotoTextureParams& params) {
  std::string problem;
  if (!mesh.Validate(&problem)) throw InvalidInputError("photo texture: " + problem, "mesh");
  if (mesh.corner_uvs.empty()) throw InvalidInputError("photo texture: the mesh has no UVs", "mesh");
  if (photo.width <= 0 || photo.height <= 0 ||
      photo.pixels.size() != 3 * static_cast<std::size_t>(photo.width) * static_cast<std::size_t>(photo.height)) {
    throw InvalidInputError("photo texture: the photo's pixels do not match its size", "photo");
  }
  if (photo.width != camera.width || photo.height != camera.height) {
    throw InvalidInputError("photo texture: the camera's image size differs from the photo's", "camera");
  }
  if (params.size < 16 || params.size > 8192) throw InvalidInputError("photo texture: size out of [16, 8192]", "size");
  if (!(params.grazing_cos >= 0.0f && params.grazing_cos < params.full_cos && params.full_cos <= 1.0f)) {
    throw InvalidInputError("photo texture: need 0 <= grazing_cos < full_cos <= 1", "grazing_cos");
  }
  if (!(params.depth_tolerance_pixels >= 0.0f) || !(params.fill_radius >= 1.0f)) {
    throw InvalidInputError("photo texture: depth tolerance must be >= 0 and fill radius >= 1", "params");
  }
  if (!(params.delight_min_facing >= 0.0f && params.delight_min_facing < 1.0f) ||
      !(params.delight_least > 0.0f && params.delight_least <= 1.0f && params.delight_most >= 1.0f)) {
    throw InvalidInputError("photo texture: need 0 <= delight_min_facing < 1 and 0 < delight_least <= 1 <= delight_most",
                            "delight");
  }
  if (params.png_compression < 0 || params.png_compression > 9) {
    throw InvalidInputError("photo texture: png_compression out of [0, 9]", "png_compression");
  }
}

std::vector<std::uint8_t> SkinTriangles(const Mesh& mesh) {
  std::vector<std::uint8_t> skin(mesh.triangle_count(), 1);
  if (mesh.triangle_parts.empty()) return skin;
  for (std::size_t t = 0; t < skin.size(); ++t) {
    skin[t] = RoleOfPart(mesh.part_names[mesh.triangle_parts[t]]) == PartRole::kSkin ? 1 : 0;
  }
  return skin;
}

// The skin triangles whose UVs lie in `tile`.
std::vector<std::uint8_t> InTile(const Mesh& mesh, const std::vector<std::uint8_t>& skin_triangle, glm::ivec2 tile) {
  std::vector<std::uint8_t> in(skin_triangle.size(), 0);
  for (std::size_t t = 0; t < in.size(); ++t) in[t] = skin_triangle[t] && photo_texture::UvTile(mesh, t) == tile ? 1 : 0;
  return in;
}

TexelLayers EmptyLayers(int size) {
  const std::size_t count = static_cast<std::size_t>(size) * static_cast<std::size_t>(size);
  return {size, std::vector<glm::vec3>(count), std::vector<glm::vec3>(count), std::vector<float>(count, 0.0f),
          std::vector<float>(count, 0.0f), std::vector<std::uint8_t>(count, 0), std::vector<std::uint8_t>(count, 0),
          std::vector<std::uint8_t>(count, 0), std::vector<float>(count, 0.0f), std::vector<glm::vec3>(count),
          std::vector<float>(count, 0.0f), std::vector<float>(count, 0.0f), std::vector<float>(count, 0.0f)};
}

RgbImage ToImage(int size, const std::vector<glm::vec3>& colours) {
  RgbImage image{size, size, std::vector<std::uint8_t>(3 * colours.size())};
  for (std::size_t i = 0; i < colours.size(); ++i) {
    for (int k = 0; k < 3; ++k) image.pixels[3 * i + static_cast<std::size_t>(k)] = ToByte(colours[i][k]);
  }
  return image;
}

RgbImage CoverageImage(const TexelLayers& layers) {
  std::vector<glm::vec3> colours(layers.skin.size());
  for (std::size_t i = 0; i < colours.size(); ++i) {
    colours[i] = {layers.direct_weight[i], layers.mirror_weight[i], layers.skin[i] ? 1.0f : 0.0f};
  }
  return ToImage(layers.size, colours);
}

PhotoTextureStats Measure(const TexelLayers& layers, const photo_texture::MirrorPartners& mirror) {
  PhotoTextureStats stats{.mirror_pairs = mirror.pairs, .mirror_partner_error = mirror.mean_error};
  std::size_t skin = 0, seen = 0, mirrored = 0;
  for (std::size_t i = 0; i < layers.skin.size(); ++i) {
    if (!layers.skin[i]) continue;
    ++skin;
    if (layers.direct_weight[i] > 0.0f) ++seen;
    if (layers.direct_weight[i] < 1.0f && layers.mirror_weight[i] > 0.0f) ++mirrored;
  }
  const double total = std::max<double>(1.0, static_cast<double>(skin));
  stats.seen_fraction = static_cast<double>(seen) / total;
  stats.mirrored_fraction = static_cast<double>(mirrored) / total;
  std::size_t filled = 0;
  for (std::size_t i = 0; i < layers.skin.size(); ++i) {
    filled += layers.skin[i] && layers.direct_weight[i] == 0.0f && layers.mirror_weight[i] == 0.0f ? 1 : 0;
  }
  stats.filled_fraction = static_cast<double>(filled) / total;
  return stats;
}

// A skin UV tile beyond the main one (the back of a head laid out beside its
// face): it mostly shows what the photo does not, so half the size does.
PhotoTextureTile BakeOtherTile(const Mesh& mesh, const std::vector<std::uint8_t>& skin_triangle, glm::ivec2 tile,
                               const RasterView& camera, const RgbImage& photo, const PhotoSkinMask& mask,
                               const photo_texture::MirrorPartners& mirror, const photo_texture::CheekRegion& cheeks,
                               const photo_texture::HairSource& hair, const PhotoTextureParams& params,
                               const PhotoLighting& lighting, float light_reference, const glm::vec3& skin_colour,
                               const photo_texture::SkinShading& shading) {
  PhotoTextureParams half = params;
  half.size = std::max(16, params.size / 2);
  half.fill_radius = std::max(1.0f, params.fill_radius / 2.0f);
  TexelLayers layers = EmptyLayers(half.size);
  photo_texture::ProjectPhoto(mesh, skin_triangle, InTile(mesh, skin_triangle, tile), camera, photo, mask, mirror, cheeks,
                              hair, half, lighting, layers);
  photo_texture::DivideOutLight(layers, light_reference, params);
  photo_texture::BalanceMirrorLight(layers);
  return {tile, ToImage(half.size, photo_texture::FillTexels(layers, skin_colour, shading, half.fill_radius)), {}};
}

}  // namespace

PhotoTexture BakePhotoTexture(const Mesh& mesh, const RasterView& camera, const RgbImage& photo,
                              const PhotoTextureParams& params, const PhotoSkinMask& mask, const PhotoHair& hair,
                              const PhotoLighting& lighting) {
  CheckInputs(mesh, camera, photo, params);
  if (!mask.empty() && mask.weight.size() != static_cast<std::size_t>(mask.width) * static_cast<std::size_t>(mask.height)) {
    throw InvalidInputError("photo texture: the mask's weights do not match its size", "mask");
  }
  if (hair.head.weight.size() != static_cast<std::size_t>(hair.head.width) * static_cast<std::size_t>(hair.head.height) &&
      !hair.head.empty()) {
    throw InvalidInputError("photo texture: the hair's head mask weights do not match its size", "hair");
  }
  const std::vector<std::uint8_t> skin_triangle = SkinTriangles(mesh);
  std::vector<std::uint8_t> skin_vertex(mesh.vertex_count(), 0);
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    if (skin_triangle[t]) for (std::uint32_t v : mesh.triangles[t]) skin_vertex[v] = 1;
  }
  Stopwatch clock;
  const photo_texture::MirrorPartners mirror = photo_texture::FindMirrorPartners(mesh, skin_vertex);
  const double partner_seconds = clock.Lap();
  photo_texture::HairSource hair_source{&hair.head, {}, hair.colour};
  int hairline_bins = 0;
  if (hair.found && !hair.head.empty()) {
    hair_source.scalp = photo_texture::FindScalp(mesh);
    glm::vec3 photo_skin(0.0f);
    if (photo_texture::PhotoSkinMedian(photo, mask, photo_skin)) hair_source.skin_colour = photo_skin;
    hairline_bins = photo_texture::FitHairlineToPhoto(mesh, skin_vertex, camera, photo, mask, hair_source);
  }
  const photo_texture::CheekRegion cheeks = photo_texture::FindCheeks(mesh);
  const std::vector<glm::ivec2> tiles = photo_texture::SkinUvTiles(mesh, skin_triangle);
  PhotoTexture result;
  result.main_tile = tiles.front();
  TexelLayers layers = EmptyLayers(params.size);
  const std::vector<std::uint8_t> main_triangles = InTile(mesh, skin_triangle, result.main_tile);
  photo_texture::ProjectPhoto(mesh, skin_triangle, main_triangles, camera, photo, mask, mirror, cheeks, hair_source,
                              params, lighting, layers);
  if (hair_source.scalp.found) photo_texture::AddPaintedHairDetail(mesh, main_triangles, layers);
  const double project_seconds = clock.Lap();
  const float light_reference = photo_texture::MedianSeenShade(layers);
  photo_texture::DivideOutLight(layers, light_reference, params);
  photo_texture::BalanceMirrorLight(layers);
  result.skin_colour = photo_texture::EstimateSkinColour(layers);
  const photo_texture::SkinShading shading = photo_texture::EstimateSkinShading(layers, result.skin_colour);
  result.texture = ToImage(params.size, photo_texture::FillTexels(layers, result.skin_colour, shading, params.fill_radius));
  result.coverage = CoverageImage(layers);
  result.stats = Measure(layers, mirror);
  result.stats.hairline_front = hair_source.scalp.found ? hair_source.scalp.Hairline(0.0f) : 0.0;
  result.stats.hairline_bins_from_photo = hairline_bins;
  result.direct_weight = std::move(layers.direct_weight);
  result.mirror_weight = std::move(layers.mirror_weight);
  for (std::size_t k = 1; k < tiles.size(); ++k) {
    result.other_tiles.push_back(BakeOtherTile(mesh, skin_triangle, tiles[k], camera, photo, mask, mirror, cheeks,
                                               hair_source, params, lighting, light_reference, result.skin_colour,
                                               shading));
  }
  result.stats.fill_seconds = clock.Lap();
  result.image = EncodePng(result.texture.pixels, result.texture.width, result.texture.height, 3, "photo_skin.png",
                           params.png_compression);
  for (PhotoTextureTile& tile : result.other_tiles) {
    const std::string name = "photo_skin_" + std::to_string(tile.tile.x) + "_" + std::to_string(tile.tile.y) + ".png";
    tile.image = EncodePng(tile.texture.pixels, tile.texture.width, tile.texture.height, 3, name, params.png_compression);
  }
  result.stats.encode_seconds = clock.Lap();
  result.stats.partner_seconds = partner_seconds;
  result.stats.project_seconds = project_seconds;
  result.material = Material{.name = "photo_skin", .base_colour = glm::vec4(1.0f), .roughness = 0.6f};
  return result;
}

}  // namespace facerig
