// Rounds the mouth opening of a lip shape. The control face has three points
// on each lip margin, so a shape authored on it opens the mouth as a diamond;
// "oh" and "oo" are round. The posed margins are moved onto an ellipse through
// the posed corners and the middle of each lip, and each margin vertex's
// correction spreads to the skin of its own lip with a short falloff.
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "default_head/internal.h"

namespace facerig::default_head {
namespace {

constexpr double kFalloff = 0.45;  // cm: how far a margin correction reaches into the lip

// 1 on the skin of the upper lip side of the mouth, 0 on the lower.
std::vector<double> UpperSide(const HeadGeometry& head) {
  const ControlMesh& c = head.control;
  std::vector<double> upper(c.names.size(), 0.0), lower(c.names.size(), 0.0);
  for (const char* name : {"lip_upper_inner", "lip_upper_outer", "subnasale"}) {
    upper[c.Find(name)] = 1.0;
    for (const char* side : {"_L", "_R"}) {
      if (std::string(name) != "subnasale") upper[c.Find(std::string(name) + side)] = 1.0;
    }
  }
  for (const char* name : {"lip_lower_inner", "lip_lower_outer"}) {
    lower[c.Find(name)] = 1.0;
    for (const char* side : {"_L", "_R"}) lower[c.Find(std::string(name) + side)] = 1.0;
  }
  const std::vector<double> u = Apply(head.subdivision, upper), l = Apply(head.subdivision, lower);
  std::vector<double> side(u.size());
  for (std::size_t v = 0; v < u.size(); ++v) side[v] = u[v] >= l[v] ? 1.0 : 0.0;
  return side;
}

// Vertical corrections of one margin chain onto its half of the ellipse.
std::vector<double> MarginCorrections(const HeadGeometry& head, const std::vector<glm::dvec3>& deltas,
                                      const std::vector<std::uint32_t>& chain, double sign) {
  auto posed = [&](std::uint32_t v) { return head.positions[v] + deltas[v]; };
  const glm::dvec3 right = posed(head.control.mouth.corner_a), left = posed(head.control.mouth.corner_b);
  const double centre_x = 0.5 * (left.x + right.x), half_width = 0.5 * (left.x - right.x);
  const double corner_y = 0.5 * (left.y + right.y);
  const double height = sign * (posed(chain[chain.size() / 2]).y - corner_y);
  std::vector<double> corrections;
  for (std::uint32_t v : chain) {
    const double t = std::clamp((posed(v).x - centre_x) / half_width, -1.0, 1.0);
    const double target = corner_y + sign * std::max(height, 0.0) * std::sqrt(1.0 - t * t);
    corrections.push_back(target - posed(v).y);
  }
  return corrections;
}

}  // namespace

void RoundMouthOpening(const HeadGeometry& head, std::vector<glm::dvec3>& deltas) {
  const std::vector<double> upper_side = UpperSide(head);
  const std::vector<double> up = MarginCorrections(head, deltas, head.upper_lip, 1.0);
  const std::vector<double> down = MarginCorrections(head, deltas, head.lower_lip, -1.0);
  std::vector<glm::dvec3> skin_correction(head.skin_count, glm::dvec3(0.0));
  for (std::uint32_t v = 0; v < head.skin_count; ++v) {
    const bool upper = upper_side[v] > 0.5;
    const std::vector<std::uint32_t>& chain = upper ? head.upper_lip : head.lower_lip;
    const std::vector<double>& correction = upper ? up : down;
    double nearest = std::numeric_limits<double>::max();
    std::size_t at = 0;
    for (std::size_t i = 0; i < chain.size(); ++i) {
      const double d = glm::length(head.positions[v] - head.positions[chain[i]]);
      if (d < nearest) nearest = d, at = i;
    }
    if (nearest > 3.0 * kFalloff) continue;
    skin_correction[v].y = correction[at] * std::exp(-std::pow(nearest / kFalloff, 2.0));
  }
  for (std::uint32_t v = 0; v < head.skin_count; ++v) deltas[v] += skin_correction[v];
  for (std::uint32_t i = 0; i < head.mouth_inner.count; ++i) {
    deltas[head.mouth_inner.first + i] += head.inner_follow[i] * skin_correction[head.inner_source[i]];
  }
}

}  // namespace facerig::default_head
