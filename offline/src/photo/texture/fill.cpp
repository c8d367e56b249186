// What the photo does not show: a skin colour estimated from the cheeks, and
// the seen colours diffused into the unseen texels (push-pull), fading into
// that skin colour.
#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "facerig/runtime/part_roles.h"
#include "facerig/offline/geometry/stats.h"
#include "photo/texture/internal.h"
#include "render/srgb.h"

namespace facerig::photo_texture {
namespace {

// A sample's weight in the fill. The pyramid averages by weight, so over an
// unseen region even a faint sample colours everything round it; and a sample
// the photo barely vouches for (a grazing view, a pixel the masks mostly leave
// out) is more often hair, shadow or background than skin: below a fair
// weight it counts for nothing.
float Trusted(float weight) {
  const float t = std::clamp((weight - 0.15f) / 0.35f, 0.0f, 1.0f);
  return weight * t * t * (3.0f - 2.0f * t);
}

bool IsEyePart(PartRole role) { return role == PartRole::kSclera || role == PartRole::kIris || role == PartRole::kPupil; }

// One level of the push-pull pyramid: colours and weights in [0, 1].
struct Level {
  int width = 0, height = 0;
  std::vector<glm::vec3> colour;
  std::vector<float> weight;
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x); }
};

// Half the size: each texel the weighted mean of its 2 x 2 block, its weight
// their sum (at most 1).
Level Coarser(const Level& fine) {
  Level coarse{(fine.width + 1) / 2, (fine.height + 1) / 2, {}, {}};
  coarse.colour.assign(static_cast<std::size_t>(coarse.width) * static_cast<std::size_t>(coarse.height), glm::vec3(0.0f));
  coarse.weight.assign(coarse.colour.size(), 0.0f);
  for (int y = 0; y < coarse.height; ++y) {
    for (int x = 0; x < coarse.width; ++x) {
      glm::vec3 sum(0.0f);
      float weight = 0.0f;
      for (int dy = 0; dy < 2; ++dy) {
        for (int dx = 0; dx < 2; ++dx) {
          const int fx = std::min(2 * x + dx, fine.width - 1), fy = std::min(2 * y + dy, fine.height - 1);
          const std::size_t i = fine.index(fx, fy);
          sum += fine.weight[i] * fine.colour[i];
          weight += fine.weight[i];
        }
      }
      const std::size_t c = coarse.index(x, y);
      coarse.colour[c] = weight > 0.0f ? sum / weight : glm::vec3(0.0f);
      coarse.weight[c] = std::min(weight, 1.0f);
    }
  }
  return coarse;
}

// Each fine texel takes the coarse level (bilinearly) for what its weight lacks.
void PullFrom(const Level& coarse, Level& fine) {
  const auto at = [&](int x, int y) {
    return coarse.colour[coarse.index(std::clamp(x, 0, coarse.width - 1), std::clamp(y, 0, coarse.height - 1))];
  };
  for (int y = 0; y < fine.height; ++y) {
    const float cy = 0.5f * (static_cast<float>(y) + 0.5f) - 0.5f;
    const int y0 = static_cast<int>(std::floor(cy));
    const float ay = cy - static_cast<float>(y0);
    for (int x = 0; x < fine.width; ++x) {
      const std::size_t i = fine.index(x, y);
      if (fine.weight[i] >= 1.0f) continue;
      const float cx = 0.5f * (static_cast<float>(x) + 0.5f) - 0.5f;
      const int x0 = static_cast<int>(std::floor(cx));
      const float ax = cx - static_cast<float>(x0);
      const glm::vec3 up = glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), ax), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), ax), ay);
      fine.colour[i] = fine.weight[i] * fine.colour[i] + (1.0f - fine.weight[i]) * up;
      fine.weight[i] = 1.0f;
    }
  }
}

}  // namespace

bool CheekRegion::Contains(const glm::vec3& p) const {
  return found && (glm::length(p - centres[0]) < radius || glm::length(p - centres[1]) < radius);
}

bool FindEyeCentres(const Mesh& mesh, glm::vec3& left, glm::vec3& right) {
  if (mesh.triangle_parts.empty()) return false;
  // The eyes' centres: the eye parts' vertices either side of the midline (x = their mean).
  std::vector<std::uint8_t> eye(mesh.vertex_count(), 0);
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    if (!IsEyePart(RoleOfPart(mesh.part_names[mesh.triangle_parts[t]]))) continue;
    for (std::uint32_t v : mesh.triangles[t]) eye[v] = 1;
  }
  glm::dvec3 sum(0.0), side_sum[2] = {glm::dvec3(0.0), glm::dvec3(0.0)};
  std::size_t count = 0, side_count[2] = {0, 0};
  for (std::size_t v = 0; v < eye.size(); ++v) {
    if (eye[v]) sum += glm::dvec3(mesh.positions[v]), ++count;
  }
  if (count == 0) return false;
  const double midline = sum.x / static_cast<double>(count);
  for (std::size_t v = 0; v < eye.size(); ++v) {
    if (!eye[v]) continue;
    const int side = mesh.positions[v].x > midline ? 0 : 1;
    side_sum[side] += glm::dvec3(mesh.positions[v]), ++side_count[side];
  }
  if (side_count[0] == 0 || side_count[1] == 0) return false;
  left = glm::vec3(side_sum[0] / static_cast<double>(side_count[0]));
  right = glm::vec3(side_sum[1] / static_cast<double>(side_count[1]));
  return true;
}

CheekRegion FindCheeks(const Mesh& mesh) {
  CheekRegion cheeks;
  glm::vec3 left(0.0f), right(0.0f);
  if (!FindEyeCentres(mesh, left, right)) return cheeks;
  const glm::vec3 across = left - right;
  const float spacing = glm::length(across);
  const glm::vec3 axis = across / spacing;
  const glm::vec3 up = glm::normalize(glm::vec3(0.0f, 1.0f, 0.0f) - axis * axis.y);  // the face's +Y, square to the eyes
  // Cheeks: below the eyes by about half their spacing, a little outwards.
  cheeks.centres = {left - 0.55f * spacing * up + 0.1f * spacing * axis, right - 0.55f * spacing * up - 0.1f * spacing * axis};
  cheeks.radius = 0.35f * spacing;
  cheeks.found = spacing > 0.0f;
  return cheeks;
}

void BalanceMirrorLight(TexelLayers& layers) {
  glm::dvec3 direct[2] = {glm::dvec3(0.0), glm::dvec3(0.0)}, mirrored[2] = {glm::dvec3(0.0), glm::dvec3(0.0)};
  for (std::size_t i = 0; i < layers.skin.size(); ++i) {
    if (!layers.skin[i] || layers.direct_weight[i] < 0.5f || layers.mirror_weight[i] < 0.5f) continue;
    const double w = layers.direct_weight[i] * layers.mirror_weight[i];
    direct[layers.side[i]] += w * glm::dvec3(layers.direct_colour[i]);
    mirrored[layers.side[i]] += w * glm::dvec3(layers.mirror_colour[i]);
  }
  glm::vec3 gain[2] = {glm::vec3(1.0f), glm::vec3(1.0f)};
  for (int side = 0; side < 2; ++side) {
    for (int k = 0; k < 3; ++k) {
      // Too little overlap says nothing; a gain far from 1 is a different surface, not light.
      if (mirrored[side][k] > 1.0 && direct[side][k] > 1.0) {
        gain[side][k] = std::clamp(static_cast<float>(direct[side][k] / mirrored[side][k]), 0.5f, 2.0f);
      }
    }
  }
  for (std::size_t i = 0; i < layers.skin.size(); ++i) {
    if (layers.skin[i]) layers.mirror_colour[i] = glm::min(layers.mirror_colour[i] * gain[layers.side[i]], glm::vec3(1.0f));
  }
}

glm::vec3 EstimateSkinColour(const TexelLayers& layers) {
  const auto median = [&](bool cheeks_only) {
    std::vector<float> channels[3];
    for (std::size_t i = 0; i < layers.skin.size(); ++i) {
      if (!layers.skin[i] || layers.direct_weight[i] < 0.5f || (cheeks_only && !layers.cheek[i])) continue;
      for (int k = 0; k < 3; ++k) channels[k].push_back(layers.direct_colour[i][k]);
    }
    glm::vec3 colour(-1.0f);
    if (channels[0].size() < 64) return colour;
    for (int k = 0; k < 3; ++k) colour[k] = Median(std::move(channels[k]));
    return colour;
  };
  glm::vec3 colour = median(true);
  if (colour.x < 0.0f) colour = median(false);
  if (colour.x >= 0.0f) return colour;
  const glm::vec4 linear = RoleMaterial(PartRole::kSkin).base_colour;
  return {LinearToSrgb(linear.r), LinearToSrgb(linear.g), LinearToSrgb(linear.b)};
}

std::vector<glm::vec3> FillTexels(const TexelLayers& layers, const glm::vec3& skin_colour, const SkinShading& shading,
                                  float fill_radius) {
  // Every texel leans a little on the skin colour: over `fill_radius` texels
  // that lean adds up to full weight in the pyramid.
  const float lean = 1.0f / std::max(fill_radius * fill_radius, 1.0f);
  std::vector<Level> pyramid(1);
  Level& base = pyramid[0];
  base.width = base.height = layers.size;
  base.colour.resize(layers.skin.size());
  base.weight.resize(layers.skin.size());
  for (std::size_t i = 0; i < layers.skin.size(); ++i) {
    const float wd = layers.skin[i] ? Trusted(layers.direct_weight[i]) : 0.0f;
    const float wm = layers.skin[i] ? (1.0f - wd) * Trusted(layers.mirror_weight[i]) : 0.0f;
    // The scalp's hair colour fills what the photo leaves there, so no skin
    // diffuses onto it; under its soft edge the skin colour fills the rest,
    // so the hair does not diffuse down the temples either.
    const float coverage = layers.skin[i] ? layers.scalp[i] : 0.0f;
    const float rest = std::max(0.0f, 1.0f - wd - wm);
    const float wh = coverage * rest;
    const float ws = (1.0f - coverage) * rest * std::min(1.0f, coverage / 0.1f) + lean;
    const glm::vec3 shaded_skin = glm::min(skin_colour * (layers.skin[i] ? shading.At(layers.tilt[i]) : 1.0f), glm::vec3(1.0f));
    const glm::vec3 sum = wd * layers.direct_colour[i] + wm * layers.mirror_colour[i] + wh * layers.hair_colour[i] +
                          ws * shaded_skin;
    base.colour[i] = sum / (wd + wm + wh + ws);
    base.weight[i] = std::min(wd + wm + wh + ws, 1.0f);
  }
  while (pyramid.back().width > 1 || pyramid.back().height > 1) pyramid.push_back(Coarser(pyramid.back()));
  Level& top = pyramid.back();
  top.colour[0] = top.weight[0] * top.colour[0] + (1.0f - top.weight[0]) * skin_colour;
  top.weight[0] = 1.0f;
  for (std::size_t level = pyramid.size() - 1; level > 0; --level) PullFrom(pyramid[level], pyramid[level - 1]);
  return std::move(pyramid[0].colour);
}

}  // namespace facerig::photo_texture
