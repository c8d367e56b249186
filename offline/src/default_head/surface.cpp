// The sculpted head: an implicit function (negative inside) built from smooth
// unions of ellipsoids and capsules, the way a stylized game head is blocked
// out. The subdivided control mesh is projected onto it along rays from the
// surface origin (Mattos et al. project onto a scan along normals; a star-shaped
// analytic sculpt lets a ray from one origin do it without fold-overs).
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "default_head/internal.h"

namespace facerig::default_head {
namespace {

// Approximate distance to an axis-aligned ellipsoid (exact on the surface,
// the right sign everywhere, which is all the ray cast needs).
double Ellipsoid(const glm::dvec3& p, const glm::dvec3& centre, const glm::dvec3& radii) {
  const glm::dvec3 q = (p - centre) / radii;
  return (glm::length(q) - 1.0) * std::min({radii.x, radii.y, radii.z});
}

// The same with a p-norm (p > 2: boxier, as a skull is).
double SuperEllipsoid(const glm::dvec3& p, const glm::dvec3& centre, const glm::dvec3& radii, double power) {
  const glm::dvec3 q = glm::abs((p - centre) / radii);
  const double norm = std::pow(std::pow(q.x, power) + std::pow(q.y, power) + std::pow(q.z, power), 1.0 / power);
  return (norm - 1.0) * std::min({radii.x, radii.y, radii.z});
}

double Capsule(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, double radius) {
  const glm::dvec3 ab = b - a;
  const double t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
  return glm::length(p - (a + t * ab)) - radius;
}

// Polynomial smooth minimum: blends two shapes over a band of width k.
double SmoothMin(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - 0.25 * h * h * k;
}
double SmoothMax(double a, double b, double k) { return -SmoothMin(-a, -b, k); }

// The left half of the sculpt features that come in pairs, evaluated at |x|.
double SidedFeatures(double f, const glm::dvec3& p, bool ears) {
  const glm::dvec3 eye = Anatomy::EyeCentre(0);
  // Cheek bones, jaw line, brow ridge.
  f = SmoothMin(f, Ellipsoid(p, {4.2, -1.2, 4.7}, {2.4, 1.6, 2.3}), 2.0);
  f = SmoothMin(f, Ellipsoid(p, {3.1, -4.4, 4.8}, {2.3, 2.4, 2.3}), 2.2);  // cheeks
  f = SmoothMin(f, Ellipsoid(p, {4.2, -7.9, 1.6}, {1.3, 1.5, 2.6}), 3.0);  // jaw angle
  f = SmoothMin(f, Ellipsoid(p, {3.2, 1.9, 7.0}, {2.3, 0.9, 0.9}), 1.5);
  // Ear: a flattened lobe at the side, enough to read in silhouette.
  if (ears) f = SmoothMin(f, Ellipsoid(p, {7.4, -1.3, -1.2}, {0.8, 2.6, 1.45}), 0.5);
  // Eye socket, then the lid skin over the eyeball.
  f = SmoothMax(f, -Ellipsoid(p, {eye.x, eye.y - 0.15, 8.0}, {1.75, 1.05, 1.6}), 0.9);
  f = SmoothMin(f, glm::length(p - eye) - (Anatomy::kEyeRadius + Anatomy::kLidOffset), 0.9);
  return f;
}

}  // namespace

glm::dvec3 SurfaceOrigin() { return {0.0, -2.5, -0.5}; }

double BareHeadField(const glm::dvec3& world, bool ears) {
  const glm::dvec3 p{std::abs(world.x), world.y, world.z};  // symmetric sculpt
  // Cranium (slightly boxy, widest above the ears) and the face masses.
  double f = SuperEllipsoid(p, {0.0, 2.6, -1.3}, {7.5, 9.3, 9.4}, 2.4);
  f = SmoothMin(f, Ellipsoid(p, {0.0, -2.4, 2.2}, {5.9, 5.6, 5.8}), 2.2);
  f = SmoothMin(f, Ellipsoid(p, {0.0, -5.4, 1.2}, {5.3, 5.0, 6.0}), 2.4);
  // Chin and mouth mound.
  f = SmoothMin(f, Ellipsoid(p, {0.0, -9.4, 6.7}, {2.5, 1.8, 2.0}), 3.0);
  f = SmoothMin(f, Ellipsoid(p, {0.0, -5.9, 5.7}, {3.1, 2.6, 2.9}), 1.5);
  // Neck: an elliptic column, open downwards, buried in the head at its top,
  // widening towards the shoulders at its base.
  const double flare = 1.0 + 0.16 * std::clamp((-12.5 - p.y) / 4.0, 0.0, 1.0);
  const double neck = (std::hypot(p.x / (5.1 * flare), (p.z + 1.3) / 5.5) - 1.0) * 5.1;
  // Cut flat at the base, so rays between the rim's points end there too.
  f = SmoothMin(f, SmoothMax(SmoothMax(neck, p.y + 3.0, 1.0), -(p.y + 17.2), 0.6), 2.8);
  f = SidedFeatures(f, p, ears);
  // Nose: bridge, tip, base and wings, blended softly.
  double nose = Capsule(p, {0.0, 0.7, 7.5}, {0.0, -2.5, 9.45}, 0.62);
  nose = SmoothMin(nose, Ellipsoid(p, {0.0, -3.05, 9.55}, {0.82, 0.78, 0.88}), 1.0);
  nose = SmoothMin(nose, Ellipsoid(p, {0.0, -3.6, 8.7}, {1.25, 0.55, 0.8}), 0.6);
  nose = SmoothMin(nose, Ellipsoid(p, {1.0, -3.5, 8.5}, {0.62, 0.58, 0.72}), 0.6);
  f = SmoothMin(f, nose, 0.9);
  // Lips, kept as two rolls so a crease stays between them.
  double lips = Ellipsoid(p, {0.0, -5.78, 8.0}, {2.45, 0.58, 1.25});
  lips = SmoothMin(lips, Ellipsoid(p, {0.0, -6.9, 7.9}, {2.15, 0.72, 1.15}), 0.15);
  f = SmoothMin(f, lips, 0.3);
  return f;
}

double HeadField(const glm::dvec3& p) {
  const double bare = BareHeadField(p, true);
  const double hair = HairThickness(p);
  return hair > 0.0 ? std::min(bare, BareHeadField(p, false) - hair) : bare;
}

glm::dvec3 SurfacePoint(const glm::dvec3& direction) {
  const glm::dvec3 origin = SurfaceOrigin();
  const glm::dvec3 d = glm::normalize(direction);
  // March out to the first sign change, then bisect.
  constexpr double kStep = 0.05;
  // The origin is more than 3 cm inside everywhere.
  double inside = 3.0, outside = -1.0;
  for (double t = 3.0 + kStep; t < 40.0; t += kStep) {
    if (HeadField(origin + t * d) > 0.0) {
      outside = t;
      break;
    }
    inside = t;
  }
  if (outside < 0.0) return origin + 40.0 * d;
  for (int i = 0; i < 50; ++i) {
    const double mid = 0.5 * (inside + outside);
    (HeadField(origin + mid * d) > 0.0 ? outside : inside) = mid;
  }
  return origin + 0.5 * (inside + outside) * d;
}

}  // namespace facerig::default_head
