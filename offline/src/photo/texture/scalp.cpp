// The scalp of a head whose photo shows only its front: where hair covers
// the surface, found from the eyes, and a hair colour varied over it.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <numbers>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "photo/texture/internal.h"
#include "geometry/piecewise_linear.h"
#include "geometry/smooth_step.h"
#include "geometry/value_noise.h"

namespace facerig::photo_texture {

// High on the forehead, just above the ears at the sides, down to the nape
// behind (azimuth: degrees about the head's vertical axis from the front).
float ScalpRegion::RuleHairline(float azimuth_degrees) {
  static constexpr float kLine[][2] = {{0, 1.05f}, {35, 0.95f}, {60, 0.6f},   {80, 0.35f},
                                       {110, 0.3f}, {135, -0.1f}, {160, -0.7f}, {180, -0.9f}};
  return PiecewiseLinear(kLine, std::min(std::abs(azimuth_degrees), 180.0f));
}

float ScalpRegion::Hairline(float azimuth_degrees) const {
  // Linear between the bins' centres; beyond the outer ones the shift fades
  // out over three bins.
  const float at = (azimuth_degrees + kShiftReach) / kShiftBinDegrees;
  const float last = static_cast<float>(kShiftBins - 1);
  float shift = 0.0f;
  if (at < 0.0f) {
    shift = hairline_shift.front() * std::max(0.0f, 1.0f + at / 3.0f);
  } else if (at > last) {
    shift = hairline_shift.back() * std::max(0.0f, 1.0f - (at - last) / 3.0f);
  } else {
    const int low = std::min(static_cast<int>(at), kShiftBins - 2);
    const float t = at - static_cast<float>(low);
    shift = (1.0f - t) * hairline_shift[static_cast<std::size_t>(low)] + t * hairline_shift[static_cast<std::size_t>(low + 1)];
  }
  return RuleHairline(azimuth_degrees) + shift;
}

float ScalpRegion::Height(const glm::vec3& p) const { return glm::dot(p - eyes, up) / spacing; }

float ScalpRegion::Azimuth(const glm::vec3& p) const {
  const glm::vec3 d = (p - eyes) / spacing;
  // The head's vertical axis lies about 1.3 eye spacings behind the eyes.
  return std::atan2(glm::dot(d, across), glm::dot(d, forward) + 1.3f) * 180.0f / std::numbers::pi_v<float>;
}

float ScalpRegion::Coverage(const glm::vec3& p) const {
  if (!found) return 0.0f;
  const float above = Height(p) - Hairline(Azimuth(p));
  return SmoothStep(-0.1f, 0.15f, above);
}

float ScalpRegion::HairMayShow(const glm::vec3& p) const {
  if (!found) return 0.0f;
  // A hairline the photo placed has the fringe above it already.
  if (hairline_from_photo) return Coverage(p);
  // A fringe over the forehead, not hair hanging beside the temples.
  const float forehead = SmoothStep(0.4f, 0.6f, Height(p)) *
                         SmoothStep(70.0f, 40.0f, std::abs(Azimuth(p)));
  return std::max(forehead, Coverage(p));
}

glm::vec3 ScalpRegion::Vary(const glm::vec3& colour, const glm::vec3& p) const {
  const glm::vec3 d = (p - eyes) / spacing;
  const float broad = ValueNoise(4.0f * d, 21), fine = ValueNoise(13.0f * d + glm::vec3(17.0f), 22);
  return glm::clamp(colour * (1.0f + 0.12f * broad + 0.07f * fine), glm::vec3(0.0f), glm::vec3(1.0f));
}

ScalpRegion FindScalp(const Mesh& mesh) {
  ScalpRegion scalp;
  glm::vec3 left(0.0f), right(0.0f);
  if (!FindEyeCentres(mesh, left, right)) return scalp;
  scalp.spacing = glm::length(left - right);
  if (!(scalp.spacing > 0.0f)) return scalp;
  scalp.eyes = 0.5f * (left + right);
  scalp.across = (left - right) / scalp.spacing;
  scalp.up = glm::normalize(glm::vec3(0.0f, 1.0f, 0.0f) - scalp.across * scalp.across.y);
  scalp.forward = glm::cross(scalp.across, scalp.up);
  scalp.found = true;
  return scalp;
}

}  // namespace facerig::photo_texture
