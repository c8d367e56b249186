#include "facerig/offline/openings/eyes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include <Eigen/Eigenvalues>
#include <glm/geometric.hpp>

namespace facerig {

namespace {

// Lid points moved farther than this fraction of the eye width on average
// mean the detector missed the eye (the built-in stylized head's misses and
// re-meshed ICT faces' hits lie on either side: docs/benchmarks.md,
// "Measurements behind the defaults").
constexpr float kMissedEye = 0.15f;

// dlib's six points of an eye, in order: corner, two upper-lid points,
// corner, two lower-lid points.
struct EyePoints {
  std::size_t first;  // 36 or 42
  std::size_t corner(bool second) const { return second ? first + 3 : first; }
};
constexpr EyePoints kEyes[] = {{36}, {42}};

// An opening taken for an eye: its vertex chain and the ends of its first
// principal axis, matched to the detected corners.
struct EyeOpening {
  const std::vector<std::uint32_t>* loop = nullptr;
  std::size_t first_end = 0;  // position in *loop of the end nearest corner(false)
  std::size_t last_end = 0;
  float width = 0.0f;         // the detected eye's corner distance
};

// The opening near a detected eye: its centre within `reach` detected widths
// of the eye's centre, its size (largest distance from its centre) within
// [min_size, max_size] widths; the nearest such, or with `largest` the
// largest (the skin's opening around an eyeball whose iris is a hole too).
std::optional<EyeOpening> FindEyeOpening(std::span<const glm::vec3> positions,
                                         const std::vector<std::vector<std::uint32_t>>& loops,
                                         std::span<const glm::vec3> points, EyePoints eye, float reach,
                                         float min_size, float max_size, bool largest) {
  glm::vec3 centre(0.0f);
  for (std::size_t k = eye.first; k < eye.first + 6; ++k) centre += points[k] / 6.0f;
  const float width = glm::length(points[eye.corner(false)] - points[eye.corner(true)]);
  const std::vector<std::uint32_t>* best = nullptr;
  float best_distance = reach * width;
  float best_size = 0.0f;
  glm::vec3 best_centre(0.0f);
  for (const auto& loop : loops) {
    glm::vec3 c(0.0f);
    float size = 0.0f;
    for (std::uint32_t v : loop) c += positions[v] / static_cast<float>(loop.size());
    for (std::uint32_t v : loop) size = std::max(size, glm::length(positions[v] - c));
    const float distance = glm::length(c - centre);
    if (size > max_size * width || size < min_size * width || distance >= reach * width) continue;
    if (largest ? size > best_size : distance < best_distance) {
      best_distance = distance;
      best_size = size;
      best = &loop;
      best_centre = c;
    }
  }
  if (best == nullptr) return std::nullopt;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (std::uint32_t v : *best) {
    const glm::vec3 d = positions[v] - best_centre;
    const Eigen::Vector3d e(d.x, d.y, d.z);
    covariance += e * e.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  const Eigen::Vector3d axis = eigen.eigenvectors().col(2);  // largest eigenvalue
  const glm::vec3 width_axis(static_cast<float>(axis.x()), static_cast<float>(axis.y()),
                             static_cast<float>(axis.z()));
  std::size_t lo = 0, hi = 0;
  for (std::size_t i = 0; i < best->size(); ++i) {
    const float along = glm::dot(positions[(*best)[i]] - best_centre, width_axis);
    if (along < glm::dot(positions[(*best)[lo]] - best_centre, width_axis)) lo = i;
    if (along > glm::dot(positions[(*best)[hi]] - best_centre, width_axis)) hi = i;
  }
  const glm::vec3 first = points[eye.corner(false)];
  const glm::vec3 last = points[eye.corner(true)];
  const glm::vec3 p_lo = positions[(*best)[lo]];
  const glm::vec3 p_hi = positions[(*best)[hi]];
  const bool lo_is_first =
      glm::length(p_lo - first) + glm::length(p_hi - last) < glm::length(p_hi - first) + glm::length(p_lo - last);
  return EyeOpening{best, lo_is_first ? lo : hi, lo_is_first ? hi : lo, width};
}

}  // namespace

std::vector<std::vector<std::uint32_t>> BoundaryLoops(std::span<const glm::vec3> positions,
                                                     std::span<const Triangle> triangles) {
  std::vector<std::uint64_t> keys;
  keys.reserve(triangles.size() * 3);
  auto key = [](std::uint32_t a, std::uint32_t b) {
    return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
  };
  for (const Triangle& t : triangles) {
    for (std::size_t e = 0; e < 3; ++e) keys.push_back(key(t[e], t[(e + 1) % 3]));
  }
  std::sort(keys.begin(), keys.end());
  constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::uint32_t> next(positions.size(), kNone);
  for (const Triangle& t : triangles) {
    for (std::size_t e = 0; e < 3; ++e) {
      const std::uint32_t a = t[e], b = t[(e + 1) % 3];
      if (a == b) continue;
      const auto range = std::equal_range(keys.begin(), keys.end(), key(a, b));
      if (range.second - range.first == 1 && next[a] == kNone) next[a] = b;
    }
  }
  std::vector<std::uint8_t> visited(positions.size(), 0);
  std::vector<std::vector<std::uint32_t>> loops;
  for (std::uint32_t start = 0; start < next.size(); ++start) {
    if (next[start] == kNone || visited[start]) continue;
    std::vector<std::uint32_t> loop;
    std::uint32_t v = start;
    while (v != kNone && !visited[v]) {
      visited[v] = 1;
      loop.push_back(v);
      v = next[v];
    }
    if (v == start && loop.size() >= 6) loops.push_back(std::move(loop));
  }
  return loops;
}

int CorrectEyeCorners(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                      std::vector<glm::vec3>& points) {
  const std::vector<std::vector<std::uint32_t>> loops = BoundaryLoops(positions, triangles);
  int moved = 0;
  for (const EyePoints eye : kEyes) {
    const std::optional<EyeOpening> opening = FindEyeOpening(positions, loops, points, eye, 0.5f, 0.25f, 1.0f, false);
    if (!opening) continue;
    const glm::vec3 new_first = positions[(*opening->loop)[opening->first_end]];
    const glm::vec3 new_last = positions[(*opening->loop)[opening->last_end]];
    // Only a small correction: a far-away extreme means the loop is not this eye.
    const float limit = 0.3f * opening->width;
    if (glm::length(new_first - points[eye.corner(false)]) < limit &&
        glm::length(new_last - points[eye.corner(true)]) < limit) {
      points[eye.corner(false)] = new_first;
      points[eye.corner(true)] = new_last;
      moved += 2;
    }
  }
  return moved;
}

namespace {

// The six points of `eye` on `opening`: the corners at the ends of its
// principal axis, the lid points on its upper and lower chains at the
// detected points' places along the axis. Nullopt for a degenerate axis.
std::optional<std::array<glm::vec3, 6>> PointsOnOpening(std::span<const glm::vec3> positions,
                                                       const EyeOpening& opening,
                                                       std::span<const glm::vec3> points, const EyePoints eye) {
  const std::vector<std::uint32_t>& loop = *opening.loop;
  const glm::vec3 first = positions[loop[opening.first_end]];
  const glm::vec3 last = positions[loop[opening.last_end]];
  const glm::vec3 axis = last - first;
  const float length2 = glm::dot(axis, axis);
  if (!(length2 > 0.0f)) return std::nullopt;
  // The loop's two chains between the corners.
  std::vector<std::uint32_t> chains[2];
  for (std::size_t i = opening.first_end; i != opening.last_end; i = (i + 1) % loop.size()) {
    chains[0].push_back(loop[i]);
  }
  for (std::size_t i = opening.last_end; i != opening.first_end; i = (i + 1) % loop.size()) {
    chains[1].push_back(loop[i]);
  }
  // Each chain's vertex nearest a place along the corner-to-corner axis
  // (0 at the first corner, 1 at the last).
  auto at = [&](const std::vector<std::uint32_t>& chain, float place) {
    std::uint32_t best = chain.front();
    float best_offset = 2.0f;
    for (std::uint32_t v : chain) {
      const float offset = std::abs(glm::dot(positions[v] - first, axis) / length2 - place);
      if (offset < best_offset) {
        best_offset = offset;
        best = v;
      }
    }
    return positions[best];
  };
  auto place_of = [&](glm::vec3 p) {
    return std::clamp(glm::dot(p - first, axis) / length2, 0.15f, 0.85f);
  };
  const std::size_t upper[2] = {eye.first + 1, eye.first + 2};
  const std::size_t lower[2] = {eye.first + 4, eye.first + 5};
  // The upper chain lies farther towards the detected upper points (they
  // may be far off: on the stylized head they sat on the brow).
  const glm::vec3 up = 0.5f * (points[upper[0]] + points[upper[1]] - points[lower[0]] - points[lower[1]]);
  auto chain_centre = [&](const std::vector<std::uint32_t>& chain) {
    glm::vec3 c(0.0f);
    for (std::uint32_t v : chain) c += positions[v] / static_cast<float>(chain.size());
    return c;
  };
  const bool first_is_upper = glm::dot(chain_centre(chains[0]) - chain_centre(chains[1]), up) > 0.0f;
  const std::vector<std::uint32_t>& upper_chain = chains[first_is_upper ? 0 : 1];
  const std::vector<std::uint32_t>& lower_chain = chains[first_is_upper ? 1 : 0];
  std::array<glm::vec3, 6> fitted_points;
  fitted_points[0] = first;
  fitted_points[3] = last;
  for (std::size_t k : {1, 2}) fitted_points[k] = at(upper_chain, place_of(points[eye.first + k]));
  for (std::size_t k : {4, 5}) fitted_points[k] = at(lower_chain, place_of(points[eye.first + k]));
  return fitted_points;
}

}  // namespace

EyeOpeningFit FitEyesToOpenings(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                                std::vector<glm::vec3>& points, const LandmarkMask& inside) {
  const std::vector<std::vector<std::uint32_t>> loops = BoundaryLoops(positions, triangles);
  EyeOpeningFit fit;
  for (const EyePoints eye : kEyes) {
    const std::optional<EyeOpening> opening = FindEyeOpening(positions, loops, points, eye, 0.75f, 0.2f, 0.8f, true);
    if (!opening) continue;
    const std::optional<std::array<glm::vec3, 6>> on_opening = PointsOnOpening(positions, *opening, points, eye);
    if (!on_opening) continue;
    const std::array<glm::vec3, 6>& fitted_points = *on_opening;
    // A far move means the opening is not this eye.
    bool near = true;
    for (std::size_t k = 0; k < 6; ++k) {
      near = near && glm::length(fitted_points[k] - points[eye.first + k]) < 0.75f * opening->width;
    }
    if (!near) continue;
    // Lid points near the opening are kept (ICT's upper lid landmarks lie
    // above its margin; on re-meshed ICT faces moving them there doubled
    // their error), unless the detector missed the eye or put them inside.
    float lid_move = 0.0f;
    for (std::size_t k : {1, 2, 4, 5}) lid_move += glm::length(fitted_points[k] - points[eye.first + k]) / 4.0f;
    const bool missed = lid_move > kMissedEye * opening->width;
    for (std::size_t k = 0; k < 6; ++k) {
      const std::size_t point = eye.first + k;
      if (k == 0 || k == 3 || missed || inside[point]) {
        points[point] = fitted_points[k];
        fit.moved[point] = true;
      }
    }
    ++fit.eyes;
  }
  return fit;
}

}  // namespace facerig

