// How closed an opening is: its margins found from the template's closing
// expression, and the gap left between them in a pose.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <set>
#include <utility>

#include <glm/geometric.hpp>

#include "facerig/offline/error.h"
#include "facerig/offline/openings/gaps.h"

namespace facerig {


namespace {

// Shortest path along mesh edges (neutral lengths) from `from` to `to` through
// vertices in [region_first, region_last) that `allowed` lets through; empty if
// none.
std::vector<std::uint32_t> ShortestEdgePath(std::span<const glm::vec3> neutral,
                                            std::span<const Triangle> triangles,
                                            std::size_t region_first, std::size_t region_last,
                                            const std::vector<bool>& allowed, std::uint32_t from,
                                            std::uint32_t to) {
  const auto in_region = [&](std::uint32_t v) {
    return v >= region_first && v < region_last && allowed[v - region_first];
  };
  std::vector<std::vector<std::uint32_t>> neighbours(region_last - region_first);
  for (const Triangle& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k];
      const std::uint32_t b = t[(k + 1) % 3];
      if (!in_region(a) || !in_region(b)) continue;
      neighbours[a - region_first].push_back(b);
      neighbours[b - region_first].push_back(a);
    }
  }
  const double unreached = std::numeric_limits<double>::infinity();
  std::vector<double> distance(neighbours.size(), unreached);
  std::vector<std::uint32_t> previous(neighbours.size(), to);
  using Entry = std::pair<double, std::uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  distance[from - region_first] = 0.0;
  queue.emplace(0.0, from);
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (v == to) break;
    if (d > distance[v - region_first]) continue;
    for (const std::uint32_t w : neighbours[v - region_first]) {
      const double through_v = d + glm::length(neutral[w] - neutral[v]);
      if (through_v < distance[w - region_first]) {
        distance[w - region_first] = through_v;
        previous[w - region_first] = v;
        queue.emplace(through_v, w);
      }
    }
  }
  if (distance[to - region_first] == unreached) return {};
  std::vector<std::uint32_t> path{to};
  while (path.back() != from) path.push_back(previous[path.back() - region_first]);
  std::reverse(path.begin(), path.end());
  return path;
}

glm::dvec3 ClosestPointOnSegment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double length2 = glm::dot(ab, ab);
  if (!(length2 > 0.0)) return a;
  return a + std::clamp(glm::dot(p - a, ab) / length2, 0.0, 1.0) * ab;
}

// How far each upper margin vertex is from the lower margin polyline.
OpeningGap EyeGap(std::span<const glm::vec3> positions, const OpeningMargins& margins) {
  OpeningGap gap;
  const std::vector<std::uint32_t>& lower = margins.lower_margin;
  if (lower.size() < 2 || !(margins.width > 0.0)) return gap;
  const float x_first = positions[lower.front()].x;
  const float x_last = positions[lower.back()].x;
  double sum = 0.0;
  for (const std::uint32_t upper : margins.upper) {
    const glm::dvec3 u(positions[upper]);
    if (u.x < std::min(x_first, x_last) || u.x > std::max(x_first, x_last)) continue;
    double distance = std::numeric_limits<double>::infinity();
    // Below the lower margin: its height at u.x, on the spanning segment nearest u.
    double nearest_spanning = std::numeric_limits<double>::infinity();
    double depth = 0.0;
    for (std::size_t i = 0; i + 1 < lower.size(); ++i) {
      const glm::dvec3 a(positions[lower[i]]);
      const glm::dvec3 b(positions[lower[i + 1]]);
      distance = std::min(distance, glm::length(u - ClosestPointOnSegment(u, a, b)));
      if (u.x < std::min(a.x, b.x) || u.x > std::max(a.x, b.x) || a.x == b.x) continue;
      const glm::dvec3 at_x = a + (u.x - a.x) / (b.x - a.x) * (b - a);
      if (glm::length(u - at_x) < nearest_spanning) {
        nearest_spanning = glm::length(u - at_x);
        depth = at_x.y - u.y;
      }
    }
    sum += distance / margins.width;
    gap.max_gap = std::max(gap.max_gap, distance / margins.width);
    gap.max_crossing = std::max(gap.max_crossing, depth / margins.width);
    ++gap.measured_vertices;
  }
  if (gap.measured_vertices > 0) gap.mean_gap = sum / static_cast<double>(gap.measured_vertices);
  return gap;
}

// How far apart each pair of lip margin vertices is.
OpeningGap MouthGap(std::span<const glm::vec3> positions, const OpeningMargins& margins) {
  OpeningGap gap;
  if (margins.upper.empty() || !(margins.width > 0.0)) return gap;
  double sum = 0.0;
  for (std::size_t i = 0; i < margins.upper.size(); ++i) {
    const glm::vec3 u = positions[margins.upper[i]];
    const glm::vec3 l = positions[margins.lower[i]];
    const double d = glm::length(u - l) / margins.width;
    sum += d;
    gap.max_gap = std::max(gap.max_gap, d);
    gap.max_crossing = std::max(gap.max_crossing, (l.y - u.y) / margins.width);
  }
  gap.mean_gap = sum / static_cast<double>(margins.upper.size());
  gap.measured_vertices = margins.upper.size();
  return gap;
}

}  // namespace

OpeningMargins FindEyelidMargins(const Mesh& neutral_mesh, std::span<const glm::vec3> blink,
                                 std::size_t region_first, std::size_t region_last) {
  const std::span<const glm::vec3> neutral = neutral_mesh.positions;
  const std::span<const Triangle> triangles = neutral_mesh.triangles;
  if (blink.size() != neutral.size()) throw MeshInputError("blink", "vertex count differs");
  region_last = std::min(region_last, neutral.size());
  if (region_first >= region_last) throw MeshInputError("blink", "empty region");
  double largest = 0.0;
  for (std::size_t v = region_first; v < region_last; ++v) {
    largest = std::max(largest, static_cast<double>(glm::length(blink[v] - neutral[v])));
  }
  OpeningMargins margins;
  margins.kind = OpeningKind::kEye;
  std::vector<bool> off_upper_lid(region_last - region_first, true);
  float lo = 0.0f;
  float hi = 0.0f;
  bool any_moving = false;
  for (std::size_t u = region_first; u < region_last; ++u) {
    const double motion = glm::length(blink[u] - neutral[u]);
    if (!(motion > 0.5 * largest)) continue;
    off_upper_lid[u - region_first] = false;
    // The vertex below that the upper one reaches.
    double best = 0.1 * motion;
    std::size_t partner = u;
    for (std::size_t l = region_first; l < region_last; ++l) {
      if (neutral[l].y >= neutral[u].y) continue;
      if (glm::length(neutral[l] - neutral[u]) < 0.3 * motion) continue;
      const double d = glm::length(blink[l] - blink[u]);
      if (d < best) {
        best = d;
        partner = l;
      }
    }
    // The eye's width: the x extent of the upper lid (everything moving that much).
    if (!any_moving) lo = hi = neutral[u].x;
    any_moving = true;
    lo = std::min(lo, neutral[u].x);
    hi = std::max(hi, neutral[u].x);
    if (partner == u) continue;
    margins.upper.push_back(static_cast<std::uint32_t>(u));
    margins.lower.push_back(static_cast<std::uint32_t>(partner));
  }
  if (margins.upper.empty()) throw MeshInputError("blink", "no eyelid vertices meet");
  margins.width = hi - lo;
  // Only the ends are joined: a path forced through every partner zig-zags where
  // a partner lies off the margin row (ICT has one, just below it).
  const auto by_x = [&](std::uint32_t a, std::uint32_t b) { return neutral[a].x < neutral[b].x; };
  const auto [first, last] = std::minmax_element(margins.lower.begin(), margins.lower.end(), by_x);
  off_upper_lid[*first - region_first] = off_upper_lid[*last - region_first] = true;
  margins.lower_margin =
      ShortestEdgePath(neutral, triangles, region_first, region_last, off_upper_lid, *first, *last);
  if (margins.lower_margin.size() < 2) {
    throw MeshInputError("blink", "no mesh path along the lower lid joins its margin vertices");
  }
  return margins;
}

OpeningMargins FindLipMargins(std::span<const glm::vec3> neutral, std::span<const glm::vec3> open,
                              std::span<const glm::vec3> closed, std::size_t region_first,
                              std::size_t region_last) {
  if (open.size() != neutral.size()) throw MeshInputError("open mouth", "vertex count differs");
  if (closed.size() != neutral.size()) throw MeshInputError("closed mouth", "vertex count differs");
  region_last = std::min(region_last, neutral.size());
  double largest = 0.0;
  for (std::size_t v = region_first; v < region_last; ++v) {
    largest = std::max(largest, static_cast<double>(glm::length(closed[v] - open[v])));
  }
  // mouthClose moves both lips (mostly the lower one, up): search both ways.
  std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;  // (upper, lower)
  for (std::size_t m = region_first; m < region_last; ++m) {
    const double motion = glm::length(closed[m] - open[m]);
    if (!(motion > 0.3 * largest)) continue;
    double best = std::numeric_limits<double>::infinity();
    std::size_t partner = m;
    for (std::size_t other = region_first; other < region_last; ++other) {
      if (glm::length(open[other] - open[m]) < 0.3 * motion) continue;
      const double d = glm::length(closed[other] - closed[m]);
      if (d < best) {
        best = d;
        partner = other;
      }
    }
    if (partner == m || !(best < 0.1 * glm::length(open[partner] - open[m]))) continue;
    const bool above = open[m].y > open[partner].y;
    pairs.emplace(static_cast<std::uint32_t>(above ? m : partner), static_cast<std::uint32_t>(above ? partner : m));
  }
  if (pairs.empty()) throw MeshInputError("closed mouth", "the lips meet nowhere");
  OpeningMargins margins;
  margins.kind = OpeningKind::kMouth;
  float lo = neutral[pairs.begin()->first].x;
  float hi = lo;
  for (const auto& [upper, lower] : pairs) {
    margins.upper.push_back(upper);
    margins.lower.push_back(lower);
    lo = std::min({lo, neutral[upper].x, neutral[lower].x});
    hi = std::max({hi, neutral[upper].x, neutral[lower].x});
  }
  margins.width = hi - lo;
  return margins;
}

OpeningGap MeasureOpeningGap(std::span<const glm::vec3> positions, const OpeningMargins& margins) {
  return margins.kind == OpeningKind::kEye ? EyeGap(positions, margins) : MouthGap(positions, margins);
}

}  // namespace facerig
