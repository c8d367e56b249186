// The photo's own light taken out of its colours: the shading fit's
// spherical-harmonic lighting evaluated at each sample's surface normal,
// relative to its median over the squarely seen skin.
#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/photo/fit.h"
#include "facerig/offline/geometry/stats.h"
#include "photo/texture/internal.h"

namespace facerig::photo_texture {
namespace {

// A shade this low is not the skin's light: the harmonics went astray.
constexpr float kLeastShade = 0.02f;

glm::vec3 DivideOut(const glm::vec3& colour, float shade, float reference, const PhotoTextureParams& params) {
  if (!(shade > kLeastShade)) return colour;
  const float brightest = std::max({colour.r, colour.g, colour.b});
  const float factor = std::max(std::clamp(shade / reference, params.delight_least, params.delight_most), brightest);
  return factor > 0.0f ? colour / factor : colour;
}

}  // namespace

PhotoShade::PhotoShade(const PhotoLighting& lighting, const PhotoTextureParams& params, float facing_sign)
    : lighting_(lighting), params_(params), facing_sign_(facing_sign),
      active_(params.delight && lighting.coefficients.size() == 9) {}

float PhotoShade::At(const glm::vec3& world_normal) const {
  if (!active_) return 0.0f;
  glm::vec3 n = lighting_.rotation * (facing_sign_ * world_normal);
  const float length = glm::length(n);
  if (!(length > 0.0f)) return 0.0f;
  n /= length;
  // The lighting was fitted on normals facing the camera: it extrapolates badly beyond.
  const float least = params_.delight_min_facing;
  if (n.z < least) {
    const glm::vec2 across(n.x, n.y);
    const float side = glm::length(across);
    if (!(side > 1e-6f)) return 0.0f;
    n = glm::vec3(across / side * std::sqrt(1.0f - least * least), least);
  }
  const float shade = Luma(EvaluatePhotoLighting(lighting_.coefficients, n));
  return std::isfinite(shade) && shade > kLeastShade ? shade : 0.0f;
}

float MedianSeenShade(const TexelLayers& layers) {
  std::vector<float> shades;
  for (std::size_t i = 0; i < layers.skin.size(); ++i) {
    if (layers.skin[i] && layers.direct_weight[i] >= 0.99f && layers.scalp[i] <= 0.0f && layers.direct_shade[i] > 0.0f) {
      shades.push_back(layers.direct_shade[i]);
    }
  }
  return shades.empty() ? 0.0f : static_cast<float>(Median(std::move(shades)));
}

void DivideOutLight(TexelLayers& layers, float reference, const PhotoTextureParams& params) {
  if (!(reference > kLeastShade)) return;
  for (std::size_t i = 0; i < layers.skin.size(); ++i) {
    if (!layers.skin[i]) continue;
    if (layers.direct_weight[i] > 0.0f) {
      layers.direct_colour[i] = DivideOut(layers.direct_colour[i], layers.direct_shade[i], reference, params);
    }
    if (layers.mirror_weight[i] > 0.0f) {
      layers.mirror_colour[i] = DivideOut(layers.mirror_colour[i], layers.mirror_shade[i], reference, params);
    }
  }
}

}  // namespace facerig::photo_texture
