// The lid margins onto the photo's lids (photo_eye_fit.h).
#include "photo/fit/eye_fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "facerig/offline/landmarks/dlib68.h"
#include "facerig/offline/openings/eyes.h"
#include "facerig/runtime/part_roles.h"
#include "geometry/smooth_step.h"

namespace facerig {
namespace {

// An eye whose lids are less than this many eye widths apart is not fitted.
constexpr float kMinOpening = 0.12f;

bool IsEyeballPart(PartRole role) {
  return role == PartRole::kSclera || role == PartRole::kIris || role == PartRole::kPupil || role == PartRole::kEyeLayer;
}

// One eye's six landmarks in the frame of its corners: t along the corner
// axis (0 at the first corner, 1 at the other), the offset square to it in
// pixels (positive downwards for an upright face).
class LidLines {
 public:
  explicit LidLines(std::span<const glm::vec2> eye) : a_(eye[0]), b_(eye[3]) {
    const glm::vec2 axis = b_ - a_;
    width_ = std::max(glm::length(axis), 1e-3f);
    u_ = axis / width_;
    n_ = glm::vec2(-u_.y, u_.x);
    if (n_.y < 0.0f) n_ = -n_;  // downwards in the image
    upper_ = Line({eye[0], eye[1], eye[2], eye[3]});
    lower_ = Line({eye[0], eye[5], eye[4], eye[3]});
  }

  float width() const { return width_; }
  // Mean distance between the lids at their two middle points, pixels.
  float opening() const { return 0.5f * ((lower_[1].y - upper_[1].y) + (lower_[2].y - upper_[2].y)); }
  glm::vec2 down() const { return n_; }
  glm::vec2 centre() const { return 0.5f * (a_ + b_); }
  float Along(glm::vec2 p) const { return glm::dot(p - a_, u_) / width_; }
  float Across(glm::vec2 p) const { return glm::dot(p - a_, n_); }
  // The lid's point at t (0..1), upper or lower.
  glm::vec2 At(float t, bool upper) const {
    const std::array<glm::vec2, 4>& line = upper ? upper_ : lower_;
    t = std::clamp(t, 0.0f, 1.0f);
    float offset = line[3].y;
    for (std::size_t k = 0; k + 1 < line.size(); ++k) {
      if (t > line[k + 1].x) continue;
      const float span = std::max(line[k + 1].x - line[k].x, 1e-6f);
      offset = line[k].y + (line[k + 1].y - line[k].y) * std::clamp((t - line[k].x) / span, 0.0f, 1.0f);
      break;
    }
    return a_ + t * (b_ - a_) + offset * n_;
  }

 private:
  // (t, offset) of each point, sorted by t.
  std::array<glm::vec2, 4> Line(std::array<glm::vec2, 4> points) const {
    for (glm::vec2& p : points) p = glm::vec2(Along(p), Across(p));
    std::sort(points.begin(), points.end(), [](glm::vec2 l, glm::vec2 r) { return l.x < r.x; });
    return points;
  }

  glm::vec2 a_, b_, u_{1.0f, 0.0f}, n_{0.0f, 1.0f};
  float width_ = 1.0f;
  std::array<glm::vec2, 4> upper_{}, lower_{};
};

// The skin's boundary loop round an eye: its projected centre within half an
// eye width of the landmarks' corners' middle, no wider than two eye widths.
const std::vector<std::uint32_t>* EyeLoop(const std::vector<std::vector<std::uint32_t>>& loops,
                                          const std::vector<glm::vec2>& pixels, const LidLines& lids) {
  const std::vector<std::uint32_t>* best = nullptr;
  float best_distance = 0.5f * lids.width();
  for (const std::vector<std::uint32_t>& loop : loops) {
    glm::vec2 centre(0.0f), low(std::numeric_limits<float>::max()), high(std::numeric_limits<float>::lowest());
    for (const std::uint32_t v : loop) centre += pixels[v], low = glm::min(low, pixels[v]), high = glm::max(high, pixels[v]);
    centre /= static_cast<float>(loop.size());
    const float distance = glm::distance(centre, lids.centre());
    if (distance < best_distance && glm::length(high - low) < 2.0f * lids.width()) best = &loop, best_distance = distance;
  }
  return best;
}

struct EyeTargets {
  std::vector<std::uint32_t> vertices;
  std::vector<glm::vec2> pixels;
  glm::vec3 centre{0.0f};  // of the rim, mesh units
  float width = 0.0f;      // the rim's corner-to-corner length, mesh units
};

// Each rim vertex's place on the photo's lid: t from the rim's own corners,
// upper or lower by its side of the line between them.
EyeTargets TargetsOnLids(const std::vector<std::uint32_t>& loop, const std::vector<glm::vec2>& pixels,
                         const std::vector<glm::vec3>& posed, const LidLines& lids) {
  auto along = [&](std::uint32_t v) { return lids.Along(pixels[v]); };
  const auto [first, last] = std::minmax_element(loop.begin(), loop.end(), [&](std::uint32_t l, std::uint32_t r) { return along(l) < along(r); });
  const float t0 = along(*first), t1 = along(*last);
  const glm::vec2 p0 = pixels[*first], p1 = pixels[*last];
  const glm::vec2 chord = p1 - p0;
  EyeTargets targets;
  targets.width = glm::distance(posed[*first], posed[*last]);
  if (t1 - t0 < 1e-3f || targets.width <= 0.0f) return targets;
  for (const std::uint32_t v : loop) {
    const float t = (along(v) - t0) / (t1 - t0);
    // Upper: above the chord between the rim's corners, as the face is upright.
    const glm::vec2 d = pixels[v] - p0;
    const glm::vec2 off_chord = d - chord * (glm::dot(d, chord) / glm::dot(chord, chord));
    const bool upper = glm::dot(off_chord, lids.down()) < 0.0f;
    targets.vertices.push_back(v);
    targets.pixels.push_back(lids.At(t, upper));
    targets.centre += posed[v] / static_cast<float>(loop.size());
  }
  return targets;
}

std::vector<std::uint8_t> EyeballVertices(const Mesh& surface) {
  std::vector<std::uint8_t> eyeball(surface.vertex_count(), 0);
  if (surface.triangle_parts.empty()) return eyeball;
  for (std::size_t t = 0; t < surface.triangle_count(); ++t) {
    if (!IsEyeballPart(RoleOfPart(surface.part_names[surface.triangle_parts[t]]))) continue;
    for (const std::uint32_t v : surface.triangles[t]) eyeball[v] = 1;
  }
  return eyeball;
}

std::vector<Triangle> SkinTriangles(const Mesh& surface) {
  std::vector<Triangle> skin;
  for (std::size_t t = 0; t < surface.triangle_count(); ++t) {
    if (surface.triangle_parts.empty() || RoleOfPart(surface.part_names[surface.triangle_parts[t]]) == PartRole::kSkin) {
      skin.push_back(surface.triangles[t]);
    }
  }
  return skin;
}

// Each eyeball (and the layers over it) moves as its rim did on average, so
// that the iris stays in the middle of the moved opening.
void MoveEyeballsWithRims(const std::vector<EyeTargets>& eyes, const std::vector<std::uint8_t>& eyeball,
                          const std::vector<glm::vec3>& moved, std::vector<glm::vec3>& posed, std::vector<glm::vec3>& rest) {
  std::vector<glm::vec3> shift(eyes.size(), glm::vec3(0.0f));
  for (std::size_t e = 0; e < eyes.size(); ++e) {
    for (const std::uint32_t v : eyes[e].vertices) shift[e] += (moved[v] - posed[v]) / static_cast<float>(eyes[e].vertices.size());
  }
  for (std::size_t v = 0; v < posed.size(); ++v) {
    if (!eyeball[v]) continue;
    std::size_t nearest = 0;
    for (std::size_t e = 1; e < eyes.size(); ++e) {
      if (glm::distance(posed[v], eyes[e].centre) < glm::distance(posed[v], eyes[nearest].centre)) nearest = e;
    }
    if (glm::distance(posed[v], eyes[nearest].centre) > 1.5f * eyes[nearest].width) continue;
    posed[v] += shift[nearest];
    rest[v] += shift[nearest];
  }
}

}  // namespace

LidMarginFit FitLidMarginsToPhoto(const Mesh& surface, std::span<const glm::vec2> landmarks,
                                  std::span<const std::uint32_t> landmark_vertices, const ScaledOrthoCamera& camera,
                                  int width, int height, std::vector<glm::vec3>& posed, std::vector<glm::vec3>& rest) {
  LidMarginFit fit;
  if (landmarks.size() != 68 || landmark_vertices.size() != 68 || rest.size() != posed.size()) return fit;
  std::vector<glm::vec2> pixels(posed.size());
  for (std::size_t v = 0; v < posed.size(); ++v) pixels[v] = ProjectPixel(camera, posed[v], width, height);
  const std::vector<std::vector<std::uint32_t>> loops = BoundaryLoops(posed, SkinTriangles(surface));
  std::vector<std::uint32_t> vertices;
  std::vector<glm::vec2> targets;
  std::vector<EyeTargets> eyes;
  for (const std::size_t first : {dlib68::kRightEyeFirst, dlib68::kLeftEyeFirst}) {
    const LidLines lids(landmarks.subspan(first, 6));
    // A closed or squeezed eye says where the lids are in that expression,
    // not at rest (the rest face takes the same offsets): left as it is.
    if (lids.opening() < kMinOpening * lids.width()) continue;
    const std::vector<std::uint32_t>* loop = EyeLoop(loops, pixels, lids);
    if (loop == nullptr) continue;
    EyeTargets eye = TargetsOnLids(*loop, pixels, posed, lids);
    if (eye.vertices.empty()) continue;
    vertices.insert(vertices.end(), eye.vertices.begin(), eye.vertices.end());
    targets.insert(targets.end(), eye.pixels.begin(), eye.pixels.end());
    fit.margins += eye.vertices.size();
    eyes.push_back(std::move(eye));
  }
  fit.eyes = static_cast<int>(eyes.size());
  if (eyes.empty()) return fit;
  // The other landmark vertices stay where the deformation put them.
  for (std::size_t k = 0; k < 68; ++k) {
    if (k >= dlib68::kRightEyeFirst && k <= dlib68::kLeftEyeLast) continue;
    vertices.push_back(landmark_vertices[k]);
    targets.push_back(pixels[landmark_vertices[k]]);
  }
  std::vector<glm::vec3> moved = posed;
  RbfDeformToLandmarks(moved, vertices, targets, camera, width, height);
  const std::vector<std::uint8_t> eyeball = EyeballVertices(surface);
  MoveEyeballsWithRims(eyes, eyeball, moved, posed, rest);
  for (std::size_t v = 0; v < posed.size(); ++v) {
    if (eyeball[v]) continue;
    float weight = 0.0f;
    for (const EyeTargets& eye : eyes) {
      weight = std::max(weight, 1.0f - SmoothStep(0.75f * eye.width, 1.5f * eye.width, glm::distance(posed[v], eye.centre)));
    }
    const glm::vec3 offset = weight * (moved[v] - posed[v]);
    posed[v] += offset;
    rest[v] += offset;
  }
  return fit;
}

}  // namespace facerig
