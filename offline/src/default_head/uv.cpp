// UVs of the default head. The skin is a closed head whose only outer
// opening is the bottom of the neck, so it is a disc (the eye and mouth
// openings are holes in it): an azimuthal map about the crown, with the
// neck opening on the rim, needs no seam. The radius grows with the polar
// angle from the crown, fastest through the face's band so the face gets
// the texels and the crown and neck fewer. Eyeballs: a disc about the gaze
// axis (iris and pupil concentric in the middle, the back pole on the rim),
// its radius growing like sin(polar / 2) so the iris gets the texels.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "default_head/internal.h"
#include "default_head/angles.h"

namespace facerig::default_head {
namespace {

// Radial texel density along the polar angle: a floor, a bump over the face
// (polar angles of about 40 to 130 degrees from the crown) and a small one
// over the neck, whose texels would otherwise stretch into streaks.
struct Bump {
  double amplitude, centre, width;  // radians
};
constexpr double kDensityFloor = 0.3;
constexpr Bump kBumps[] = {{2.0, 78.0 * kPi / 180.0, 45.0 * kPi / 180.0},
                           {0.5, 152.0 * kPi / 180.0, 14.0 * kPi / 180.0}};

// The integral of the density from 0 to `polar`.
double DensityIntegral(double polar) {
  double integral = kDensityFloor * polar;
  for (const Bump& b : kBumps) {
    integral += b.amplitude * b.width * std::sqrt(kPi) / 2.0 *
                (std::erf((polar - b.centre) / b.width) - std::erf(-b.centre / b.width));
  }
  return integral;
}

}  // namespace

glm::dvec2 SkinUv(const glm::dvec3& position) {
  const glm::dvec3 d = glm::normalize(position - SurfaceOrigin());
  const double polar = std::acos(std::clamp(d.y, -1.0, 1.0));
  const double azimuth = std::atan2(d.x, d.z);  // 0: the face, +: the character's left
  const double radius = 0.5 * DensityIntegral(polar) / DensityIntegral(kPi);
  // Image rows grow downwards: the face sits upright in the lower half, seen
  // from the front (the character's left on the image's right).
  return {0.5 + radius * std::sin(azimuth), 0.5 + radius * std::cos(azimuth)};
}

glm::dvec2 EyeUv(const glm::dvec3& position, int side) {
  const glm::dvec3 d = glm::normalize(position - Anatomy::EyeCentre(side));
  const double polar = std::acos(std::clamp(d.z, -1.0, 1.0));  // from the gaze axis
  const double around = std::atan2(d.y, d.x);
  const double radius = EyeUvRadius(polar);
  return {0.5 + radius * std::cos(around), 0.5 - radius * std::sin(around)};
}

double EyeUvRadius(double polar_angle) { return 0.5 * std::sin(0.5 * polar_angle); }

std::vector<glm::vec2> HeadUvs(const HeadGeometry& head) {
  // Parts without a texture (the tongue) get the texture's centre.
  std::vector<glm::vec2> uvs(head.positions.size(), glm::vec2(0.5f));
  for (std::uint32_t v = 0; v < head.skin_count; ++v) uvs[v] = glm::vec2(SkinUv(head.positions[v]));
  for (std::uint32_t i = 0; i < head.eyeballs.count; ++i) {
    const std::uint32_t v = head.eyeballs.first + i;
    uvs[v] = glm::vec2(EyeUv(head.positions[v], head.positions[v].x > 0.0 ? 0 : 1));
  }
  for (std::size_t i = 0; i < head.teeth_uvs.size(); ++i) uvs[head.teeth_upper.first + i] = glm::vec2(head.teeth_uvs[i]);
  for (std::size_t i = 0; i < head.mouth_uvs.size(); ++i) uvs[head.mouth_inner.first + i] = glm::vec2(head.mouth_uvs[i]);
  return uvs;
}

}  // namespace facerig::default_head
