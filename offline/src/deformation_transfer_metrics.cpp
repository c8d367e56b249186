// Error measures for deformation transfer against a known answer (issue 6).
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <utility>

#include <glm/geometric.hpp>

#include "facerig/offline/deformation_transfer.h"

namespace facerig {

ExpressionError MeasureExpressionError(std::span<const glm::vec3> rest,
                                       std::span<const glm::vec3> truth,
                                       std::span<const glm::vec3> result,
                                       std::size_t region_first, std::size_t region_last,
                                       double moved_fraction, double still_fraction) {
  if (truth.size() != rest.size()) throw TransferInputError("truth", "vertex count differs from rest");
  if (result.size() != rest.size()) {
    throw TransferInputError("result", "vertex count differs from rest");
  }
  region_last = std::min(region_last, rest.size());
  ExpressionError error;
  if (region_first >= region_last) return error;
  double largest = 0.0;
  for (std::size_t v = region_first; v < region_last; ++v) {
    largest = std::max(largest, static_cast<double>(glm::length(truth[v] - rest[v])));
  }
  double moved_truth = 0.0;
  double moved_error = 0.0;
  double still_motion = 0.0;
  for (std::size_t v = region_first; v < region_last; ++v) {
    const double motion = glm::length(truth[v] - rest[v]);
    const double err = glm::length(result[v] - truth[v]);
    error.max_error = std::max(error.max_error, err);
    if (motion > moved_fraction * largest) {
      moved_truth += motion;
      moved_error += err;
      ++error.moved_vertices;
    } else if (motion < still_fraction * largest) {
      still_motion += glm::length(result[v] - rest[v]);
      ++error.still_vertices;
    }
  }
  if (error.moved_vertices == 0 || !(moved_truth > 0.0)) return error;
  const double mean_truth = moved_truth / static_cast<double>(error.moved_vertices);
  error.relative_error = moved_error / static_cast<double>(error.moved_vertices) / mean_truth;
  if (error.still_vertices > 0) {
    error.leak = still_motion / static_cast<double>(error.still_vertices) / mean_truth;
  }
  return error;
}

double Percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double rank = std::ceil(fraction * static_cast<double>(values.size()));
  const auto index = static_cast<std::size_t>(std::clamp(rank, 1.0, static_cast<double>(values.size())));
  return values[index - 1];
}

EyelidMargins FindEyelidMargins(std::span<const glm::vec3> neutral,
                                std::span<const glm::vec3> blink, std::size_t region_first,
                                std::size_t region_last) {
  if (blink.size() != neutral.size()) throw TransferInputError("blink", "vertex count differs");
  region_last = std::min(region_last, neutral.size());
  double largest = 0.0;
  for (std::size_t v = region_first; v < region_last; ++v) {
    largest = std::max(largest, static_cast<double>(glm::length(blink[v] - neutral[v])));
  }
  EyelidMargins margins;
  float lo = 0.0f;
  float hi = 0.0f;
  bool any_moving = false;
  for (std::size_t u = region_first; u < region_last; ++u) {
    const double motion = glm::length(blink[u] - neutral[u]);
    if (!(motion > 0.5 * largest)) continue;
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
  if (margins.upper.empty()) throw TransferInputError("blink", "no eyelid vertices meet");
  margins.eye_width = hi - lo;
  return margins;
}

EyelidGap MeasureEyelidGap(std::span<const glm::vec3> positions, const EyelidMargins& margins) {
  EyelidGap gap;
  if (margins.upper.empty() || !(margins.eye_width > 0.0)) return gap;
  double sum = 0.0;
  for (std::size_t i = 0; i < margins.upper.size(); ++i) {
    const glm::vec3 u = positions[margins.upper[i]];
    const glm::vec3 l = positions[margins.lower[i]];
    const double d = glm::length(u - l) / margins.eye_width;
    sum += d;
    gap.max_gap = std::max(gap.max_gap, d);
    gap.max_crossing = std::max(gap.max_crossing, (l.y - u.y) / margins.eye_width);
  }
  gap.mean_gap = sum / static_cast<double>(margins.upper.size());
  return gap;
}

LipMargins FindLipMargins(std::span<const glm::vec3> neutral, std::span<const glm::vec3> open,
                          std::span<const glm::vec3> closed, std::size_t region_first,
                          std::size_t region_last) {
  if (open.size() != neutral.size()) throw TransferInputError("open mouth", "vertex count differs");
  if (closed.size() != neutral.size()) throw TransferInputError("closed mouth", "vertex count differs");
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
  if (pairs.empty()) throw TransferInputError("closed mouth", "the lips meet nowhere");
  LipMargins margins;
  float lo = neutral[pairs.begin()->first].x;
  float hi = lo;
  for (const auto& [upper, lower] : pairs) {
    margins.upper.push_back(upper);
    margins.lower.push_back(lower);
    lo = std::min({lo, neutral[upper].x, neutral[lower].x});
    hi = std::max({hi, neutral[upper].x, neutral[lower].x});
  }
  margins.mouth_width = hi - lo;
  return margins;
}

LipGap MeasureLipGap(std::span<const glm::vec3> positions, const LipMargins& margins) {
  LipGap gap;
  if (margins.upper.empty() || !(margins.mouth_width > 0.0)) return gap;
  double sum = 0.0;
  for (std::size_t i = 0; i < margins.upper.size(); ++i) {
    const glm::vec3 u = positions[margins.upper[i]];
    const glm::vec3 l = positions[margins.lower[i]];
    const double d = glm::length(u - l) / margins.mouth_width;
    sum += d;
    gap.max_gap = std::max(gap.max_gap, d);
    gap.max_crossing = std::max(gap.max_crossing, (l.y - u.y) / margins.mouth_width);
  }
  gap.mean_gap = sum / static_cast<double>(margins.upper.size());
  return gap;
}

}  // namespace facerig
