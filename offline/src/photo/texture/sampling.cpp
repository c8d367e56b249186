// The photo's colour at surface points: visibility from the z-buffer, a
// weight by how squarely the surface faces the camera, bilinear sampling;
// walked over every texel of the skin's UV islands.
#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "facerig/offline/photo/skin_mask.h"
#include "facerig/runtime/part_roles.h"
#include "facerig/runtime/rig_builder.h"
#include "photo/texture/internal.h"
#include "geometry/parallel_for.h"
#include "render/uv_raster.h"
#include "geometry/smooth_step.h"

namespace facerig::photo_texture {
namespace {

// ProjectPhoto's bands of texel rows, shared out over the cores: more than
// the cores, as the face fills some bands more than others.
constexpr std::size_t kProjectionBands = 16;

// Opaque parts only: lashes and the transparent layers over the eyes do not
// hide the skin behind them. `shows_skin`: per occluder, whether it is skin.
Mesh Occluders(const Mesh& mesh, const std::vector<std::uint8_t>& skin_triangle, std::vector<std::uint8_t>& shows_skin) {
  Mesh occluders;
  occluders.positions = mesh.positions;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const PartRole role = mesh.triangle_parts.empty() ? PartRole::kSkin : RoleOfPart(mesh.part_names[mesh.triangle_parts[t]]);
    if (role == PartRole::kLashes || role == PartRole::kEyeLayer) continue;
    occluders.triangles.push_back(mesh.triangles[t]);
    shows_skin.push_back(skin_triangle[t]);
  }
  return occluders;
}

// The photo seen through the camera, with its z-buffer.
class PhotoView {
 public:
  PhotoView(const Mesh& mesh, const std::vector<std::uint8_t>& skin_triangle, const RasterView& camera,
            const RgbImage& photo, const PhotoSkinMask& mask, const HairSource& hair, const PhotoTextureParams& params)
      : camera_(camera), photo_(photo), mask_(mask), hair_(hair), params_(params),
        buffers_(Rasterize(Occluders(mesh, skin_triangle, shows_skin_), camera)) {
    towards_camera_ = glm::vec3(camera.rotation[0][2], camera.rotation[1][2], camera.rotation[2][2]);
    camera_position_ = camera.centre + camera.distance * towards_camera_;
    // Meshes wound clockwise face away from the camera where it sees them.
    std::size_t covered = 0, back = 0;
    for (std::size_t i = 0; i < buffers_.triangle_ids.size(); ++i) {
      if (buffers_.triangle_ids[i] == kNoTriangle) continue;
      ++covered;
      back += buffers_.back_facing[i];
    }
    facing_sign_ = 2 * back > covered ? -1.0f : 1.0f;
  }

  // +1, or -1 for a mesh wound clockwise (its normals point inwards).
  float facing_sign() const { return facing_sign_; }

  // The photo's weight in [0, 1] at surface point p with normal n, and its
  // colour there: skin anywhere, the head's hair above the brows.
  // Hair counts by where the colour lands (`lands_on`: p itself, or the
  // point a mirror sample is for), so the hair one side shows lower does not
  // land on the other side's skin.
  float Sample(const glm::vec3& p, const glm::vec3& n, const glm::vec3& lands_on, glm::vec3& colour) const {
    const glm::vec3 q = ProjectToImage(camera_, p);
    if (!(q.x >= 0.0f && q.y >= 0.0f && q.x < static_cast<float>(camera_.width) && q.y < static_cast<float>(camera_.height))) {
      return 0.0f;
    }
    const bool perspective = camera_.vertical_fov > 0.0f;
    const glm::vec3 towards = perspective ? glm::normalize(camera_position_ - p) : towards_camera_;
    const float facing = facing_sign_ * glm::dot(n, towards);
    float shown = MaskUnder(mask_, q.x, q.y);
    if (hair_.scalp.found && shown < 1.0f) shown = std::max(shown, hair_.scalp.HairMayShow(lands_on) * MaskUnder(*hair_.head, q.x, q.y));
    const float facing_weight = SmoothStep(params_.grazing_cos, params_.full_cos, facing);
    float weight = facing_weight * shown;
    if (weight <= 0.0f) return 0.0f;
    const std::size_t pixel = buffers_.index(static_cast<int>(q.x), static_cast<int>(q.y));
    // Where the photo shows an eye or teeth there, the skin point is behind them.
    const std::int32_t front = buffers_.triangle_ids[pixel];
    if (front == kNoTriangle || !shows_skin_[static_cast<std::size_t>(front)]) return 0.0f;
    // Depth changes across a pixel by its slope: allow for it.
    const float slope = std::min(std::sqrt(std::max(0.0f, 1.0f - facing * facing)) / facing, 8.0f);
    if (q.z < buffers_.depths[pixel] - PixelSize(p) * (params_.depth_tolerance_pixels + slope)) return 0.0f;
    colour = Bilinear(q.x - 0.5f, q.y - 0.5f);
    if (hair_.IsHairAt(lands_on, colour)) {
      weight = facing_weight * hair_.scalp.HairMayShow(lands_on) * MaskUnder(*hair_.head, q.x, q.y);
    }
    return weight;
  }

 private:
  // World units per photo pixel at p.
  float PixelSize(const glm::vec3& p) const {
    const float h = static_cast<float>(camera_.height);
    if (camera_.vertical_fov <= 0.0f) return 2.0f * camera_.half_extent / h;
    return 2.0f * std::tan(0.5f * camera_.vertical_fov) * glm::length(camera_position_ - p) / h;
  }

  glm::vec3 Pixel(int x, int y) const {
    x = std::clamp(x, 0, photo_.width - 1), y = std::clamp(y, 0, photo_.height - 1);
    const std::uint8_t* c = &photo_.pixels[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(photo_.width) + static_cast<std::size_t>(x))];
    return glm::vec3(c[0], c[1], c[2]) * (1.0f / 255.0f);
  }

  // The least mask weight of the pixels Bilinear mixes at (x, y): a colour
  // with any of an excluded pixel in it counts no more than that pixel.
  static float MaskUnder(const PhotoSkinMask& mask, float x, float y) {
    const int x0 = static_cast<int>(std::floor(x - 0.5f)), y0 = static_cast<int>(std::floor(y - 0.5f));
    return std::min(std::min(mask.At(x0, y0), mask.At(x0 + 1, y0)), std::min(mask.At(x0, y0 + 1), mask.At(x0 + 1, y0 + 1)));
  }

  bool ShowsSkin(int x, int y) const {
    if (x < 0 || y < 0 || x >= camera_.width || y >= camera_.height) return false;
    const std::int32_t front = buffers_.triangle_ids[buffers_.index(x, y)];
    return front != kNoTriangle && shows_skin_[static_cast<std::size_t>(front)];
  }

  // Bilinear over the neighbouring pixels that show skin: no eye white,
  // teeth or background bleeds into the skin's edges.
  glm::vec3 Bilinear(float x, float y) const {
    const float fx = std::floor(x), fy = std::floor(y);
    const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
    const float ax = x - fx, ay = y - fy;
    glm::vec3 sum(0.0f);
    float total = 0.0f;
    for (int dy = 0; dy < 2; ++dy) {
      for (int dx = 0; dx < 2; ++dx) {
        if (!ShowsSkin(x0 + dx, y0 + dy)) continue;
        const float w = (dx != 0 ? ax : 1.0f - ax) * (dy != 0 ? ay : 1.0f - ay);
        sum += w * Pixel(x0 + dx, y0 + dy);
        total += w;
      }
    }
    return total > 1e-6f ? sum / total : Pixel(static_cast<int>(x + 0.5f), static_cast<int>(y + 0.5f));
  }

  const RasterView& camera_;
  const RgbImage& photo_;
  const PhotoSkinMask& mask_;
  const HairSource& hair_;
  const PhotoTextureParams& params_;
  std::vector<std::uint8_t> shows_skin_;  // declared before buffers_: Occluders fills it
  RasterBuffers buffers_;
  glm::vec3 towards_camera_{0.0f, 0.0f, 1.0f};
  glm::vec3 camera_position_{0.0f};
  float facing_sign_ = 1.0f;
};

// A point of the surface by barycentrics, with its normal.
struct SurfacePoint {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f};
};

SurfacePoint Interpolate(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
                         const std::array<std::uint32_t, 3>& v, double w0, double w1, double w2) {
  const auto mix = [&](const std::vector<glm::vec3>& values) {
    return glm::vec3(w0 * glm::dvec3(values[v[0]]) + w1 * glm::dvec3(values[v[1]]) + w2 * glm::dvec3(values[v[2]]));
  };
  const glm::vec3 n = mix(normals);
  const float length = glm::length(n);
  return {mix(positions), length > 0.0f ? n / length : n};
}

// The triangle's UVs in texel coordinates (OBJ's v up; the UV tile its centre lies in).
void TexelCorners(const Mesh& mesh, std::size_t t, int size, glm::dvec2 (&uv)[3]) {
  const glm::vec2 tile(UvTile(mesh, t));
  for (int k = 0; k < 3; ++k) {
    const glm::vec2 local = mesh.corner_uvs[3 * t + static_cast<std::size_t>(k)] - tile;
    uv[k] = glm::dvec2(local.x, 1.0f - local.y) * static_cast<double>(size) - 0.5;
  }
}

// ProjectPhoto's work on the texel rows [row_begin, row_end).
void ProjectRows(const Mesh& mesh, const std::vector<std::uint8_t>& baked, const PhotoView& view, const PhotoShade& shade,
                 const std::vector<glm::vec3>& normals, const MirrorPartners& mirror, const CheekRegion& cheeks,
                 const HairSource& hair, int row_begin, int row_end, TexelLayers& layers) {
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    if (!baked[t]) continue;
    const std::array<std::uint32_t, 3> v{mesh.triangles[t][0], mesh.triangles[t][1], mesh.triangles[t][2]};
    const bool mirrored = mirror.partner[v[0]] >= 0 && mirror.partner[v[1]] >= 0 && mirror.partner[v[2]] >= 0;
    std::array<std::uint32_t, 3> m{};
    for (int k = 0; k < 3; ++k) m[k] = mirrored ? static_cast<std::uint32_t>(mirror.partner[v[k]]) : 0u;
    glm::dvec2 uv[3];
    TexelCorners(mesh, t, layers.size, uv);
    ForEachTexelIn(uv, layers.size, [&](int x, int y, double w0, double w1, double w2) {
      const SurfacePoint point = Interpolate(mesh.positions, normals, v, w0, w1, w2);
      glm::vec3 direct(0.0f), reflected(0.0f);
      const float wd = view.Sample(point.position, point.normal, point.position, direct);
      float wm = 0.0f, partner_shade = 0.0f;
      if (mirrored) {
        const SurfacePoint partner = Interpolate(mesh.positions, normals, m, w0, w1, w2);
        wm = view.Sample(partner.position, partner.normal, point.position, reflected);
        if (wm > 0.0f) partner_shade = shade.At(partner.normal);
      }
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(layers.size) + static_cast<std::size_t>(x);
      // Where UV islands overlap, the better seen surface wins.
      const float combined = wd + (1.0f - wd) * wm;
      if (layers.skin[i] && combined <= layers.direct_weight[i] + (1.0f - layers.direct_weight[i]) * layers.mirror_weight[i]) {
        return;
      }
      layers.skin[i] = 1;
      layers.direct_colour[i] = direct, layers.direct_weight[i] = wd;
      layers.mirror_colour[i] = reflected, layers.mirror_weight[i] = wm;
      layers.direct_shade[i] = wd > 0.0f ? shade.At(point.normal) : 0.0f, layers.mirror_shade[i] = partner_shade;
      layers.cheek[i] = cheeks.Contains(point.position) ? 1 : 0;
      layers.scalp[i] = hair.scalp.Coverage(point.position);
      if (layers.scalp[i] > 0.0f) layers.hair_colour[i] = hair.scalp.Vary(hair.colour, point.position);
      layers.side[i] = glm::dot(mirror.plane_normal, point.position) < mirror.plane_offset ? 1 : 0;
      layers.tilt[i] = view.facing_sign() * point.normal.y;
    }, row_begin, row_end);
  }
}

}  // namespace

glm::ivec2 UvTile(const Mesh& mesh, std::size_t t) {
  glm::vec2 centre(0.0f);
  for (int k = 0; k < 3; ++k) centre += mesh.corner_uvs[3 * t + static_cast<std::size_t>(k)] / 3.0f;
  return glm::ivec2(glm::floor(centre));
}

std::vector<glm::ivec2> SkinUvTiles(const Mesh& mesh, const std::vector<std::uint8_t>& skin_triangle) {
  std::vector<std::pair<glm::ivec2, std::size_t>> counts;
  for (std::size_t t = 0; t < skin_triangle.size(); ++t) {
    if (!skin_triangle[t]) continue;
    const glm::ivec2 tile = UvTile(mesh, t);
    auto found = std::find_if(counts.begin(), counts.end(), [&](const auto& c) { return c.first == tile; });
    if (found == counts.end()) counts.emplace_back(tile, 1);
    else ++found->second;
  }
  std::stable_sort(counts.begin(), counts.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  std::vector<glm::ivec2> tiles;
  for (const auto& c : counts) tiles.push_back(c.first);
  if (tiles.empty()) tiles.emplace_back(0, 0);
  return tiles;
}

void ProjectPhoto(const Mesh& mesh, const std::vector<std::uint8_t>& skin_triangle,
                  const std::vector<std::uint8_t>& baked, const RasterView& camera,
                  const RgbImage& photo, const PhotoSkinMask& mask, const MirrorPartners& mirror,
                  const CheekRegion& cheeks, const HairSource& hair, const PhotoTextureParams& params,
                  const PhotoLighting& lighting, TexelLayers& layers) {
  const PhotoView view(mesh, skin_triangle, camera, photo, mask, hair, params);
  const PhotoShade shade(lighting, params, view.facing_sign());
  std::vector<glm::vec3> normals(mesh.vertex_count());
  ComputeVertexNormals(mesh.positions, mesh.triangles, normals);
  // Bands of texel rows on all cores: each band visits the triangles in
  // order, so where islands overlap the same triangle wins as in one pass.
  const int bands = static_cast<int>(kProjectionBands);
  const int band_rows = std::max(1, (layers.size + bands - 1) / bands);
  ParallelFor(kProjectionBands, 1, [&](std::size_t band) {
    const int row_begin = static_cast<int>(band) * band_rows;
    ProjectRows(mesh, baked, view, shade, normals, mirror, cheeks, hair, row_begin, row_begin + band_rows, layers);
  });
}

}  // namespace facerig::photo_texture
