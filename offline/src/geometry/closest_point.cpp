#include "facerig/offline/geometry/closest_point.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "facerig/offline/error.h"

namespace facerig {
namespace {

constexpr std::uint32_t kLeafSize = 8;

float BoxDistanceSquared(glm::vec3 p, glm::vec3 lo, glm::vec3 hi) {
  const glm::vec3 d = glm::max(glm::max(lo - p, p - hi), glm::vec3(0.0f));
  return glm::dot(d, d);
}

}  // namespace

glm::vec3 ClosestPointOnTriangle(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c,
                                 glm::vec3& barycentrics) {
  const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) {
    barycentrics = {1, 0, 0};
    return a;
  }
  const glm::vec3 bp = p - b;
  const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) {
    barycentrics = {0, 1, 0};
    return b;
  }
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) {
    const float v = d1 - d3 != 0.0f ? d1 / (d1 - d3) : 0.0f;
    barycentrics = {1 - v, v, 0};
    return a + v * ab;
  }
  const glm::vec3 cp = p - c;
  const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) {
    barycentrics = {0, 0, 1};
    return c;
  }
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) {
    const float w = d2 - d6 != 0.0f ? d2 / (d2 - d6) : 0.0f;
    barycentrics = {1 - w, 0, w};
    return a + w * ac;
  }
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
    const float denom = (d4 - d3) + (d5 - d6);
    const float w = denom != 0.0f ? (d4 - d3) / denom : 0.0f;
    barycentrics = {0, 1 - w, w};
    return b + w * (c - b);
  }
  const float sum = va + vb + vc;
  if (!(sum > 0.0f)) {  // degenerate (zero-area) triangle that fell through
    barycentrics = {1, 0, 0};
    return a;
  }
  const float v = vb / sum, w = vc / sum;
  barycentrics = {1 - v - w, v, w};
  return a + ab * v + ac * w;
}

ClosestPointQuery::ClosestPointQuery(const Mesh& mesh) : positions_(mesh.positions), triangles_(mesh.triangles) {
  CheckMesh();
  ComputeNormals();
  FindBoundaryEdges();
  BuildTree();
}

void ClosestPointQuery::CheckMesh() const {
  if (positions_.empty() || triangles_.empty()) {
    throw InvalidInputError("closest point: the mesh has no vertices or no triangles");
  }
  for (std::size_t v = 0; v < positions_.size(); ++v) {
    const glm::vec3 p = positions_[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw InvalidInputError("closest point: vertex " + std::to_string(v) + " has a non-finite coordinate");
    }
  }
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    for (std::uint32_t v : triangles_[t]) {
      if (v >= positions_.size()) {
        throw InvalidInputError("closest point: triangle " + std::to_string(t) + " uses vertex " +
                                std::to_string(v) + " of " + std::to_string(positions_.size()));
      }
    }
  }
}

void ClosestPointQuery::ComputeNormals() {
  vertex_normals_.assign(positions_.size(), glm::vec3(0.0f));
  face_normals_.resize(triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const Triangle& tri = triangles_[t];
    const glm::vec3 area_normal = glm::cross(positions_[tri[1]] - positions_[tri[0]],
                                             positions_[tri[2]] - positions_[tri[0]]);
    const float length = glm::length(area_normal);
    face_normals_[t] = length > 0.0f ? area_normal / length : glm::vec3(0.0f);
    for (std::uint32_t v : tri) vertex_normals_[v] += area_normal;
  }
  for (glm::vec3& normal : vertex_normals_) {
    const float length = glm::length(normal);
    normal = length > 0.0f ? normal / length : glm::vec3(0.0f);
  }
}

// Boundary edges: used by exactly one triangle (undirected). Edge uses sorted
// by key, then one linear pass over runs of equal keys: several times faster
// than a hash map or a binary search per edge on large meshes.
void ClosestPointQuery::FindBoundaryEdges() {
  struct EdgeUse {
    std::uint64_t key;
    std::uint32_t slot;  // 3 * triangle + edge
  };
  std::vector<EdgeUse> uses;
  uses.reserve(triangles_.size() * 3);
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const Triangle& tri = triangles_[t];
    for (std::size_t e = 0; e < 3; ++e) {
      const std::uint32_t a = tri[e], b = tri[(e + 1) % 3];
      uses.push_back({(static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b),
                      static_cast<std::uint32_t>(3 * t + e)});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) { return x.key < y.key; });
  boundary_edges_.assign(triangles_.size(), 0);
  boundary_vertex_.assign(positions_.size(), 0);
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    if (j - i == 1) {
      const std::uint32_t t = uses[i].slot / 3, e = uses[i].slot % 3;
      boundary_edges_[t] = static_cast<std::uint8_t>(boundary_edges_[t] | (1u << e));
      boundary_vertex_[triangles_[t][e]] = 1;
      boundary_vertex_[triangles_[t][(e + 1) % 3]] = 1;
    }
    i = j;
  }
}

void ClosestPointQuery::BuildTree() {
  std::vector<glm::vec3> centroids(triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const Triangle& tri = triangles_[t];
    centroids[t] = (positions_[tri[0]] + positions_[tri[1]] + positions_[tri[2]]) / 3.0f;
  }
  // Per-triangle boxes: each level of the build reads one box per triangle
  // rather than three scattered vertices.
  triangle_boxes_.resize(2 * triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const Triangle& tri = triangles_[t];
    triangle_boxes_[2 * t] = glm::min(glm::min(positions_[tri[0]], positions_[tri[1]]), positions_[tri[2]]);
    triangle_boxes_[2 * t + 1] = glm::max(glm::max(positions_[tri[0]], positions_[tri[1]]), positions_[tri[2]]);
  }
  order_.resize(triangles_.size());
  for (std::uint32_t t = 0; t < order_.size(); ++t) order_[t] = t;
  nodes_.reserve(2 * triangles_.size() / kLeafSize + 2);
  nodes_.push_back({});
  Build(static_cast<std::uint32_t>(order_.size()), centroids);
  triangle_boxes_ = {};
}

void ClosestPointQuery::Build(std::uint32_t count, const std::vector<glm::vec3>& centroids) {
  // The root (node 0) is already allocated; children are allocated in
  // adjacent pairs. An explicit stack: no recursion depth limit.
  struct Task {
    std::uint32_t node, first, count;
  };
  std::vector<Task> stack{{0, 0, count}};
  while (!stack.empty()) {
    const Task task = stack.back();
    stack.pop_back();
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    glm::vec3 clo = lo, chi = hi;
    for (std::uint32_t i = task.first; i < task.first + task.count; ++i) {
      lo = glm::min(lo, triangle_boxes_[2 * order_[i]]);
      hi = glm::max(hi, triangle_boxes_[2 * order_[i] + 1]);
      clo = glm::min(clo, centroids[order_[i]]);
      chi = glm::max(chi, centroids[order_[i]]);
    }
    nodes_[task.node].lo = lo;
    nodes_[task.node].hi = hi;
    const glm::vec3 extent = chi - clo;
    if (task.count <= kLeafSize || std::max({extent.x, extent.y, extent.z}) <= 0.0f) {
      nodes_[task.node].first = task.first;
      nodes_[task.node].count = task.count;
      continue;
    }
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const std::uint32_t half = task.count / 2;
    auto begin = order_.begin() + task.first;
    std::nth_element(begin, begin + half, begin + task.count, [&](std::uint32_t a, std::uint32_t b) {
      return centroids[a][axis] < centroids[b][axis];
    });
    const auto left = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back({});
    nodes_.push_back({});
    nodes_[task.node].first = left;
    nodes_[task.node].count = 0;
    stack.push_back({left, task.first, half});
    stack.push_back({left + 1, task.first + half, task.count - half});
  }
}

ClosestPointHit ClosestPointQuery::Find(glm::vec3 query, float max_distance) const {
  return FindFiltered(query, max_distance, nullptr, 0.0f);
}

ClosestPointHit ClosestPointQuery::FindFacing(glm::vec3 query, glm::vec3 normal, float min_normal_dot,
                                              float max_distance) const {
  return FindFiltered(query, max_distance, &normal, min_normal_dot);
}

ClosestPointHit ClosestPointQuery::FindFiltered(glm::vec3 query, float max_distance, const glm::vec3* normal,
                                                float min_normal_dot) const {
  ClosestPointHit hit;
  float best = std::isfinite(max_distance) ? max_distance * max_distance
                                           : std::numeric_limits<float>::infinity();
  std::array<std::uint32_t, 128> stack;
  std::size_t top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (BoxDistanceSquared(query, node.lo, node.hi) > best) continue;
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
        const std::uint32_t t = order_[i];
        if (normal && glm::dot(face_normals_[t], *normal) < min_normal_dot) continue;
        const Triangle& tri = triangles_[t];
        glm::vec3 bary;
        const glm::vec3 p = ClosestPointOnTriangle(query, positions_[tri[0]], positions_[tri[1]],
                                                   positions_[tri[2]], bary);
        const glm::vec3 d = p - query;
        const float d2 = glm::dot(d, d);
        if (d2 < best || (d2 == best && hit.triangle >= 0 && static_cast<std::int32_t>(t) < hit.triangle)) {
          best = d2;
          hit.triangle = static_cast<std::int32_t>(t);
          hit.barycentrics = bary;
          hit.point = p;
        }
      }
      continue;
    }
    // Visit the nearer child first (pushed last).
    const std::uint32_t left = node.first;
    const float dl = BoxDistanceSquared(query, nodes_[left].lo, nodes_[left].hi);
    const float dr = BoxDistanceSquared(query, nodes_[left + 1].lo, nodes_[left + 1].hi);
    if (top + 2 > stack.size()) continue;  // cannot happen: depth is ~log2(n / 8)
    if (dl <= dr) {
      stack[top++] = left + 1;
      stack[top++] = left;
    } else {
      stack[top++] = left;
      stack[top++] = left + 1;
    }
  }
  if (hit.triangle < 0) return hit;
  const auto t = static_cast<std::size_t>(hit.triangle);
  hit.distance = std::sqrt(best);
  hit.normal = face_normals_[t];
  // On an edge: the vertex opposite it has weight 0; on a vertex: two weights are 0.
  const Triangle& tri = triangles_[t];
  const glm::vec3 b = hit.barycentrics;
  constexpr float kEps = 1e-6f;
  for (std::size_t e = 0; e < 3; ++e) {
    const std::size_t opposite = (e + 2) % 3;
    if (b[static_cast<int>(opposite)] <= kEps && (boundary_edges_[t] & (1u << e))) hit.on_boundary = true;
  }
  for (std::size_t k = 0; k < 3; ++k) {
    if (b[static_cast<int>(k)] >= 1.0f - kEps && boundary_vertex_[tri[k]]) hit.on_boundary = true;
  }
  return hit;
}

}  // namespace facerig
