// The photo's own light taken out of its colours: the shading fit's
// spherical-harmonic lighting evaluated at each surface normal, relative to
// the face's front so that the texture keeps the brightness of the photo's
// cheeks where the face looks at the camera.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "facerig/offline/photo_fit.h"
#include "photo_texture_internal.h"

namespace facerig::photo_texture {
namespace {

float Luma(const glm::vec3& c) { return 0.299f * c.r + 0.587f * c.g + 0.114f * c.b; }

// A reference brightness this low means the lighting is not the skin's.
constexpr float kLeastReference = 0.05f;

}  // namespace

Delighting::Delighting(const PhotoLighting& lighting, const PhotoTextureParams& params, float facing_sign)
    : lighting_(lighting), params_(params), facing_sign_(facing_sign) {
  if (!params.delight || lighting.coefficients.size() != 9 || !(glm::length(lighting.front) > 0.0f)) return;
  const float reference = Shade(lighting.rotation * glm::normalize(lighting.front));
  reference_ = std::isfinite(reference) && reference > kLeastReference ? reference : 0.0f;
}

// Normals turned further from the camera than the fit saw are shaded as at
// the edge of what it saw: the harmonics extrapolate badly beyond.
float Delighting::Shade(glm::vec3 n) const {
  const float least = params_.delight_min_facing;
  if (n.z < least) {
    const glm::vec2 across(n.x, n.y);
    const float length = glm::length(across);
    const glm::vec2 direction = length > 1e-6f ? across / length : glm::vec2(0.0f);
    n = glm::vec3(direction * std::sqrt(std::max(0.0f, 1.0f - least * least)), length > 1e-6f ? least : 1.0f);
  }
  return Luma(EvaluatePhotoLighting(lighting_.coefficients, n));
}

float Delighting::Factor(const glm::vec3& world_normal) const {
  if (reference_ <= 0.0f) return 1.0f;
  const glm::vec3 n = lighting_.rotation * (facing_sign_ * world_normal);
  const float length = glm::length(n);
  if (!(length > 0.0f)) return 1.0f;
  const float factor = Shade(n / length) / reference_;
  if (!std::isfinite(factor)) return 1.0f;
  return std::clamp(factor, params_.delight_least, params_.delight_most);
}

}  // namespace facerig::photo_texture
