#include "openings/contacts.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "geometry/bounding_box.h"
#include "geometry/mesh_edges.h"

namespace facerig {

namespace {

// A line of sight between a pair at rest is clear when no triangle of their
// part crosses it and no corner comes within this fraction of its length of
// its middle part (the ends are left out: the triangles around them graze it).
constexpr float kSightClearance = 0.1f;
constexpr float kSightMargin = 0.15f;
// Candidates tried per moving vertex, nearest first (each costs a path search).
constexpr std::size_t kCandidatesTried = 4;

// Cells per axis of the grid of rest triangles.
constexpr int kGridSize = 64;

constexpr float kUnvisited = std::numeric_limits<float>::infinity();

// Grid cells of the given size, packed 21 bits per axis.
std::uint64_t CellKey(glm::vec3 p, float cell, int dx, int dy, int dz) {
  const auto coordinate = [cell](float x, int d) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(x / cell)) + d +
                                      (1 << 20)) &
           0x1FFFFF;
  };
  return coordinate(p.x, dx) | coordinate(p.y, dy) << 21 | coordinate(p.z, dz) << 42;
}

}  // namespace

ContactFinder::ContactFinder(std::span<const glm::vec3> neutral, std::span<const Triangle> triangles,
                             std::span<const std::uint32_t> component_of_vertex, const OpeningParams& params)
    : params_(params),
      neutral_(neutral), triangles_(triangles), component_of_vertex_(component_of_vertex) {
  triangle_low_.reserve(triangles.size());
  triangle_high_.reserve(triangles.size());
  for (const Triangle& t : triangles) {
    triangle_low_.push_back(glm::min(neutral[t[0]], glm::min(neutral[t[1]], neutral[t[2]])));
    triangle_high_.push_back(glm::max(neutral[t[0]], glm::max(neutral[t[1]], neutral[t[2]])));
  }
  // The triangles by grid cell (compressed rows), for the lines of sight.
  if (!neutral.empty()) {
    const BoundingBox box = BoxAround(neutral);
    const glm::vec3 extent = box.extent();
    grid_origin_ = box.low;
    grid_size_ = kGridSize;
    grid_cell_ = std::max(std::max(extent.x, extent.y), std::max(extent.z, 1e-6f)) / static_cast<float>(kGridSize);
  }
  const auto cell_index = [this](int x, int y, int z) {
    return static_cast<std::size_t>(x + grid_size_ * (y + grid_size_ * z));
  };
  grid_begin_.assign(static_cast<std::size_t>(grid_size_) * grid_size_ * grid_size_ + 1, 0);
  const auto for_each_cell = [&](std::size_t j, auto&& visit) {
    const glm::ivec3 first = GridCell(triangle_low_[j]);
    const glm::ivec3 last = GridCell(triangle_high_[j]);
    for (int z = first.z; z <= last.z; ++z) {
      for (int y = first.y; y <= last.y; ++y) {
        for (int x = first.x; x <= last.x; ++x) visit(cell_index(x, y, z));
      }
    }
  };
  for (std::size_t j = 0; j < triangles.size(); ++j) {
    for_each_cell(j, [&](std::size_t c) { ++grid_begin_[c + 1]; });
  }
  for (std::size_t c = 1; c < grid_begin_.size(); ++c) grid_begin_[c] += grid_begin_[c - 1];
  grid_triangles_.resize(grid_begin_.back());
  std::vector<std::uint32_t> filled(grid_begin_.begin(), grid_begin_.end() - 1);
  for (std::size_t j = 0; j < triangles.size(); ++j) {
    for_each_cell(j, [&](std::size_t c) { grid_triangles_[filled[c]++] = static_cast<std::uint32_t>(j); });
  }
  VertexNeighbours(neutral.size(), triangles, neighbour_begin_, neighbours_);
}

void ContactFinder::Find(std::span<const glm::vec3> expression, float largest_motion,
                                   std::span<const std::int32_t> free_index,
                                   std::vector<OpeningContact>& contacts, Scratch& scratch) const {
  contacts.clear();
  if (!(largest_motion > 0.0f)) return;
  const std::size_t n = expression.size();
  const float moving_threshold = params_.contact_moving_fraction * largest_motion;
  // A partner is within one cell of its moving vertex, so the 27 cells around it hold every candidate.
  const float cell = params_.contact_reach * largest_motion;
  glm::vec3 lo(std::numeric_limits<float>::max());
  glm::vec3 hi(-std::numeric_limits<float>::max());
  for (std::size_t u = 0; u < n; ++u) {
    if (free_index[u] >= 0 && glm::length(expression[u] - neutral_[u]) > moving_threshold) {
      lo = glm::min(lo, expression[u]);
      hi = glm::max(hi, expression[u]);
    }
  }
  lo -= glm::vec3(cell);
  hi += glm::vec3(cell);
  scratch.cells.clear();
  for (std::size_t v = 0; v < n; ++v) {
    const glm::vec3 p = expression[v];
    if (glm::any(glm::lessThan(p, lo)) || glm::any(glm::greaterThan(p, hi))) continue;
    scratch.cells.emplace_back(CellKey(p, cell, 0, 0, 0), static_cast<std::uint32_t>(v));
  }
  std::sort(scratch.cells.begin(), scratch.cells.end());
  if (scratch.path_length.size() != n) scratch.path_length.assign(n, kUnvisited);

  for (std::uint32_t u = 0; u < n; ++u) {
    if (free_index[u] < 0) continue;
    const glm::vec3 motion = expression[u] - neutral_[u];
    const float moved = glm::length(motion);
    if (!(moved > moving_threshold)) continue;
    scratch.candidates.clear();
    for (int dz = -1; dz <= 1; ++dz) {
      for (int dy = -1; dy <= 1; ++dy) {
        // x is the key's lowest bits: the three cells along x are one run.
        const std::uint64_t first = CellKey(expression[u], cell, -1, dy, dz);
        const std::uint64_t last = CellKey(expression[u], cell, 1, dy, dz);
        auto it = std::lower_bound(scratch.cells.begin(), scratch.cells.end(),
                                   std::pair<std::uint64_t, std::uint32_t>{first, 0u});
        for (; it != scratch.cells.end() && it->first <= last; ++it) {
          const std::uint32_t v = it->second;
          if (v == u || component_of_vertex_[v] != component_of_vertex_[u]) continue;
          const glm::vec3 ahead = neutral_[v] - neutral_[u];
          const float apart = glm::length(ahead);
          if (apart <= params_.contact_nearest_ahead * moved || apart > params_.contact_farthest_ahead * moved) {
            continue;
          }
          if (glm::dot(ahead, motion) < params_.contact_ahead_cosine * apart * moved) continue;
          const float distance = glm::length(expression[v] - expression[u]);
          if (distance < params_.contact_reach * moved) scratch.candidates.emplace_back(distance, v);
        }
      }
    }
    std::sort(scratch.candidates.begin(), scratch.candidates.end());
    const std::size_t tried = std::min(scratch.candidates.size(), kCandidatesTried);
    for (std::size_t k = 0; k < tried; ++k) {
      const std::uint32_t v = scratch.candidates[k].second;
      const float apart = glm::length(neutral_[v] - neutral_[u]);
      if (!SightBlocked(u, v, scratch) && PathLongerThan(u, v, params_.contact_opening_detour * apart, scratch)) {
        contacts.push_back({u, v, expression[u] - expression[v]});
        break;
      }
    }
  }
}

glm::ivec3 ContactFinder::GridCell(glm::vec3 p) const {
  const glm::ivec3 cell(glm::floor((p - grid_origin_) / grid_cell_));
  return glm::clamp(cell, glm::ivec3(0), glm::ivec3(grid_size_ - 1));
}

bool ContactFinder::SightBlocked(std::uint32_t u, std::uint32_t v, Scratch& scratch) const {
  const glm::vec3 start = neutral_[u];
  const glm::vec3 across = neutral_[v] - start;
  const float length2 = glm::dot(across, across);
  const float clearance = kSightClearance * std::sqrt(length2);
  const glm::vec3 low = glm::min(start, start + across) - glm::vec3(clearance);
  const glm::vec3 high = glm::max(start, start + across) + glm::vec3(clearance);
  if (scratch.triangle_stamp.size() != triangles_.size()) scratch.triangle_stamp.assign(triangles_.size(), 0);
  if (++scratch.sight_test == 0) {  // wrapped: forget every stamp
    std::fill(scratch.triangle_stamp.begin(), scratch.triangle_stamp.end(), 0);
    scratch.sight_test = 1;
  }
  const glm::ivec3 first = GridCell(low);
  const glm::ivec3 last = GridCell(high);
  for (int z = first.z; z <= last.z; ++z) {
    for (int y = first.y; y <= last.y; ++y) {
      for (int x = first.x; x <= last.x; ++x) {
        const std::size_t c = static_cast<std::size_t>(x + grid_size_ * (y + grid_size_ * z));
        for (std::uint32_t k = grid_begin_[c]; k < grid_begin_[c + 1]; ++k) {
          const std::uint32_t j = grid_triangles_[k];
          if (scratch.triangle_stamp[j] == scratch.sight_test) continue;
          scratch.triangle_stamp[j] = scratch.sight_test;
          if (TriangleNearSight(j, u, v, clearance)) return true;
        }
      }
    }
  }
  return false;
}

bool ContactFinder::TriangleNearSight(std::uint32_t j, std::uint32_t u, std::uint32_t v,
                                                float clearance) const {
  const glm::vec3 start = neutral_[u];
  const glm::vec3 across = neutral_[v] - start;
  if (glm::any(glm::lessThan(triangle_high_[j], glm::min(start, start + across) - glm::vec3(clearance))) ||
      glm::any(glm::greaterThan(triangle_low_[j], glm::max(start, start + across) + glm::vec3(clearance)))) {
    return false;
  }
  const Triangle& t = triangles_[j];
  const auto has = [&t](std::uint32_t w) { return t[0] == w || t[1] == w || t[2] == w; };
  if (has(u) || has(v) || component_of_vertex_[t[0]] != component_of_vertex_[u]) return false;
  // A corner near the middle of the line: the surface passes close by.
  const float length2 = glm::dot(across, across);
  for (std::uint32_t w : t) {
    const glm::vec3 offset = neutral_[w] - start;
    const float s = glm::dot(offset, across) / length2;
    if (s < kSightMargin || s > 1.0f - kSightMargin) continue;
    if (glm::length(offset - s * across) < clearance) return true;
  }
  // The line through the triangle (Moller-Trumbore: start + s across = a + b1 e1 + b2 e2).
  const glm::vec3 a = neutral_[t[0]];
  const glm::vec3 e1 = neutral_[t[1]] - a;
  const glm::vec3 e2 = neutral_[t[2]] - a;
  const glm::vec3 p = glm::cross(across, e2);
  const float determinant = glm::dot(e1, p);
  if (determinant == 0.0f) return false;  // parallel to the triangle
  const float inverse = 1.0f / determinant;
  const glm::vec3 offset = start - a;
  const float b1 = glm::dot(offset, p) * inverse;
  if (b1 < 0.0f || b1 > 1.0f) return false;
  const glm::vec3 q = glm::cross(offset, e1);
  const float b2 = glm::dot(across, q) * inverse;
  if (b2 < 0.0f || b1 + b2 > 1.0f) return false;
  const float s = glm::dot(e2, q) * inverse;
  return s >= kSightMargin && s <= 1.0f - kSightMargin;
}

bool ContactFinder::PathLongerThan(std::uint32_t u, std::uint32_t v, float limit,
                                             Scratch& scratch) const {
  // A* along edges at rest, guided by the straight distance to v (never more
  // than the path): it stops at v, or once every path left is over the limit.
  const glm::vec3 goal = neutral_[v];
  auto estimate = [&](std::uint32_t w, float length) {
    return length + glm::length(goal - neutral_[w]);
  };
  scratch.queue.clear();
  scratch.visited.clear();
  scratch.path_length[u] = 0.0f;
  scratch.visited.push_back(u);
  scratch.queue.emplace_back(estimate(u, 0.0f), u);
  bool reached = false;
  while (!scratch.queue.empty()) {
    std::pop_heap(scratch.queue.begin(), scratch.queue.end(), std::greater<>());
    const auto [bound, w] = scratch.queue.back();
    scratch.queue.pop_back();
    if (bound > limit) break;
    if (w == v) {
      reached = true;
      break;
    }
    const float length = scratch.path_length[w];
    if (bound > estimate(w, length)) continue;  // a stale entry
    for (std::uint32_t k = neighbour_begin_[w]; k < neighbour_begin_[w + 1]; ++k) {
      const std::uint32_t next = neighbours_[k];
      const float next_length = length + glm::length(neutral_[next] - neutral_[w]);
      if (next_length >= scratch.path_length[next]) continue;
      if (scratch.path_length[next] == kUnvisited) scratch.visited.push_back(next);
      scratch.path_length[next] = next_length;
      scratch.queue.emplace_back(estimate(next, next_length), next);
      std::push_heap(scratch.queue.begin(), scratch.queue.end(), std::greater<>());
    }
  }
  for (std::uint32_t w : scratch.visited) scratch.path_length[w] = kUnvisited;
  return !reached;
}

}  // namespace facerig
