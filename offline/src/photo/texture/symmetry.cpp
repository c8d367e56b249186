// Mirror partners of a face's vertices: each skin vertex reflected across the
// face's symmetry plane lands next to its partner on the other side.
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/geometry/stats.h"
#include "photo/texture/internal.h"

namespace facerig::photo_texture {
namespace {

// Points bucketed in a uniform grid whose cells are `cell` wide: the nearest
// point within one cell of a query is in its 3 x 3 x 3 block.
class PointGrid {
 public:
  PointGrid(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& ids, float cell)
      : positions_(positions), cell_(cell) {
    lo_ = glm::vec3(std::numeric_limits<float>::max());
    glm::vec3 hi(-std::numeric_limits<float>::max());
    for (std::uint32_t v : ids) lo_ = glm::min(lo_, positions[v]), hi = glm::max(hi, positions[v]);
    for (int k = 0; k < 3; ++k) dims_[k] = std::clamp(static_cast<int>((hi[k] - lo_[k]) / cell) + 1, 1, 256);
    start_.assign(static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2] + 1, 0);
    for (std::uint32_t v : ids) ++start_[CellOf(positions[v]) + 1];
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    ids_.resize(ids.size());
    std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
    for (std::uint32_t v : ids) ids_[next[CellOf(positions[v])]++] = v;
  }

  // The nearest point within `cell` of q, or -1.
  std::int32_t Nearest(const glm::vec3& q) const {
    const glm::ivec3 c = Coordinates(q);
    std::int32_t best = -1;
    float best_distance = cell_ * cell_;
    for (int z = std::max(0, c.z - 1); z <= std::min(dims_[2] - 1, c.z + 1); ++z) {
      for (int y = std::max(0, c.y - 1); y <= std::min(dims_[1] - 1, c.y + 1); ++y) {
        for (int x = std::max(0, c.x - 1); x <= std::min(dims_[0] - 1, c.x + 1); ++x) {
          const std::size_t cell = Index(x, y, z);
          for (std::uint32_t i = start_[cell]; i < start_[cell + 1]; ++i) {
            const glm::vec3 d = positions_[ids_[i]] - q;
            const float distance = glm::dot(d, d);
            if (distance < best_distance) best_distance = distance, best = static_cast<std::int32_t>(ids_[i]);
          }
        }
      }
    }
    return best;
  }

 private:
  glm::ivec3 Coordinates(const glm::vec3& p) const {
    glm::ivec3 c;
    for (int k = 0; k < 3; ++k) c[k] = std::clamp(static_cast<int>(std::floor((p[k] - lo_[k]) / cell_)), -2, dims_[k] + 1);
    return c;
  }
  std::size_t Index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * dims_[1] + static_cast<std::size_t>(y)) * dims_[0] + static_cast<std::size_t>(x);
  }
  std::size_t CellOf(const glm::vec3& p) const {
    const glm::ivec3 c = glm::clamp(Coordinates(p), glm::ivec3(0), glm::ivec3(dims_[0] - 1, dims_[1] - 1, dims_[2] - 1));
    return Index(c.x, c.y, c.z);
  }

  const std::vector<glm::vec3>& positions_;
  float cell_;
  glm::vec3 lo_{0.0f};
  int dims_[3] = {1, 1, 1};
  std::vector<std::uint32_t> start_, ids_;
};

struct Plane {
  glm::vec3 normal{1.0f, 0.0f, 0.0f};
  float offset = 0.0f;
  glm::vec3 Reflect(const glm::vec3& p) const { return p - 2.0f * (glm::dot(normal, p) - offset) * normal; }
};

// The plane halfway between vertices and their partners, its normal along
// their differences (oriented as the current normal).
Plane RefinedPlane(const Plane& plane, const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& ids,
                   const PointGrid& grid) {
  glm::dvec3 direction(0.0);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::uint32_t v : ids) {
    const std::int32_t q = grid.Nearest(plane.Reflect(positions[v]));
    if (q < 0 || static_cast<std::uint32_t>(q) == v) continue;
    glm::vec3 d = positions[v] - positions[static_cast<std::size_t>(q)];
    if (glm::dot(d, plane.normal) < 0.0f) d = -d;
    direction += glm::dvec3(d);
    pairs.emplace_back(v, static_cast<std::uint32_t>(q));
  }
  if (pairs.empty() || glm::length(direction) == 0.0) return plane;
  Plane refined{glm::vec3(glm::normalize(direction)), 0.0f};
  double offset = 0.0;
  for (const auto& [a, b] : pairs) offset += glm::dot(refined.normal, 0.5f * (positions[a] + positions[b]));
  refined.offset = static_cast<float>(offset / static_cast<double>(pairs.size()));
  return refined;
}

}  // namespace

MirrorPartners FindMirrorPartners(const Mesh& mesh, const std::vector<std::uint8_t>& skin_vertex) {
  MirrorPartners mirror;
  mirror.partner.assign(mesh.vertex_count(), -1);
  std::vector<std::uint32_t> ids;
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  std::vector<float> xs;
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    if (!skin_vertex[v]) continue;
    ids.push_back(v);
    xs.push_back(mesh.positions[v].x);
    lo = glm::min(lo, mesh.positions[v]), hi = glm::max(hi, mesh.positions[v]);
  }
  if (ids.empty()) return mirror;
  // Partners further apart than 2% of the skin's size are no partners.
  const float reach = std::max(0.02f * glm::length(hi - lo), 1e-6f);
  const PointGrid grid(mesh.positions, ids, reach);
  Plane plane{glm::vec3(1.0f, 0.0f, 0.0f), Median(std::move(xs))};  // the character's left is +X
  for (int pass = 0; pass < 3; ++pass) plane = RefinedPlane(plane, mesh.positions, ids, grid);
  mirror.plane_normal = plane.normal;
  mirror.plane_offset = plane.offset;
  double error = 0.0;
  for (std::uint32_t v : ids) {
    const glm::vec3 reflected = plane.Reflect(mesh.positions[v]);
    const std::int32_t q = grid.Nearest(reflected);
    if (q < 0) continue;
    mirror.partner[v] = q;
    ++mirror.pairs;
    error += glm::length(reflected - mesh.positions[static_cast<std::size_t>(q)]);
  }
  mirror.mean_error = mirror.pairs > 0 ? error / static_cast<double>(mirror.pairs) : 0.0;
  return mirror;
}

}  // namespace facerig::photo_texture
