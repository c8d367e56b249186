// Framing the face from the mesh alone: its centre, up axis and mirror
// symmetry plane, whole-mesh and close-up views.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include <Eigen/Eigenvalues>
#include <glm/geometric.hpp>

#include "facerig/offline/geometry/closest_point.h"
#include "facerig/offline/error.h"
#include "landmarks/internal.h"

namespace facerig::landmarks_detail {
namespace {

struct AreaMoments {
  glm::dvec3 mean{0.0};
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

// Area-weighted moments: independent of how densely each region is meshed.
AreaMoments TriangleAreaMoments(std::span<const glm::vec3> positions, std::span<const Triangle> triangles) {
  AreaMoments moments;
  double area_sum = 0.0;
  for (const Triangle& t : triangles) {
    const glm::vec3 a = positions[t[0]], b = positions[t[1]], c = positions[t[2]];
    const double area = 0.5 * static_cast<double>(glm::length(glm::cross(b - a, c - a)));
    area_sum += area;
    moments.mean += area * glm::dvec3((a + b + c) / 3.0f);
  }
  if (!(area_sum > 0.0)) throw InvalidInputError("landmarks: every triangle of the mesh is degenerate");
  moments.mean /= area_sum;
  for (const Triangle& t : triangles) {
    const glm::vec3 a = positions[t[0]], b = positions[t[1]], c = positions[t[2]];
    const double area = 0.5 * static_cast<double>(glm::length(glm::cross(b - a, c - a)));
    const glm::dvec3 d = glm::dvec3((a + b + c) / 3.0f) - moments.mean;
    const Eigen::Vector3d e(d.x, d.y, d.z);
    moments.covariance += area * e * e.transpose();
  }
  return moments;
}

// Up: the principal axis nearest to +Y (the input is roughly upright).
glm::vec3 PrincipalUp(const Eigen::Matrix3d& covariance) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  int best_axis = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(eigen.eigenvectors()(1, k)) > std::abs(eigen.eigenvectors()(1, best_axis))) best_axis = k;
  }
  glm::vec3 up(static_cast<float>(eigen.eigenvectors()(0, best_axis)),
               static_cast<float>(eigen.eigenvectors()(1, best_axis)),
               static_cast<float>(eigen.eigenvectors()(2, best_axis)));
  if (up.y < 0.0f) up = -up;
  // A principal axis more than 35 degrees from +Y is not the head's up axis
  // (e.g. a face mask wider than tall): keep +Y.
  return up.y > std::cos(static_cast<float>(35.0 * kPi / 180.0)) ? glm::normalize(up) : glm::vec3(0, 1, 0);
}

// Up to ~300 vertices spread over the mesh, and the distance beyond which a
// mirrored sample counts as simply off the surface (5% of the bounding box).
struct SymmetrySamples {
  std::vector<glm::vec3> points;
  float cap = 0.0f;
};

SymmetrySamples SampleSurface(std::span<const glm::vec3> positions, std::span<const Triangle> triangles) {
  // Only vertices of triangles: stray points are not surface.
  std::vector<std::uint8_t> used(positions.size(), 0);
  for (const Triangle& t : triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
  SymmetrySamples samples;
  const std::size_t stride = std::max<std::size_t>(1, positions.size() / 300);
  for (std::size_t v = 0; v < positions.size(); v += stride) {
    if (used[v]) samples.points.push_back(positions[v]);
  }
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (!used[v]) continue;
    lo = glm::min(lo, positions[v]);
    hi = glm::max(hi, positions[v]);
  }
  samples.cap = 0.05f * glm::length(hi - lo);
  return samples;
}

// Symmetry plane through `centre` containing `up`: the lateral direction
// whose mirror image of the surface lies closest to the surface. A coarse
// scan over half a turn, then a finer one around its best angle.
glm::vec3 SymmetryLateral(const SymmetrySamples& samples, const ClosestPointQuery& surface, glm::vec3 centre,
                          glm::vec3 up) {
  const glm::vec3 a = glm::normalize(glm::cross(up, std::abs(up.z) < 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0)));
  const glm::vec3 b = glm::cross(up, a);
  auto asymmetry = [&](float theta) {
    const glm::vec3 lateral = std::cos(theta) * a + std::sin(theta) * b;
    double sum = 0.0;
    for (const glm::vec3& p : samples.points) {
      const glm::vec3 mirrored = p - 2.0f * glm::dot(p - centre, lateral) * lateral;
      sum += static_cast<double>(std::min(surface.Find(mirrored, samples.cap).distance, samples.cap));
    }
    return sum;
  };
  float best_theta = 0.0f;
  double best = std::numeric_limits<double>::infinity();
  auto try_angle = [&](float theta) {
    const double score = asymmetry(theta);
    if (score < best) {
      best = score;
      best_theta = theta;
    }
  };
  constexpr int kCoarse = 12;
  for (int i = 0; i < kCoarse; ++i) try_angle(static_cast<float>(kPi * i / kCoarse));
  const float coarse_step = static_cast<float>(kPi / kCoarse);
  const float centre_theta = best_theta;
  for (int i = -3; i <= 3; ++i) try_angle(centre_theta + coarse_step * static_cast<float>(i) / 4.0f);
  return std::cos(best_theta) * a + std::sin(best_theta) * b;
}

MeshFrame EstimateFrame(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                        const ClosestPointQuery& surface) {
  const AreaMoments moments = TriangleAreaMoments(positions, triangles);
  MeshFrame frame;
  frame.centre = glm::vec3(moments.mean);
  frame.up = PrincipalUp(moments.covariance);
  frame.lateral = SymmetryLateral(SampleSurface(positions, triangles), surface, frame.centre, frame.up);
  return frame;
}

// A coarse stand-in for a large mesh (vertex clustering on a grid of
// `cells` cells along the longest side): the front-view estimate only needs
// the overall shape, and a million-vertex scan would otherwise cost a
// closest-point structure of millions of triangles. Vertices no triangle
// uses are left out, so stray points do not count as surface.
ProxyMesh ClusterMesh(std::span<const glm::vec3> positions, std::span<const Triangle> triangles, int cells) {
  std::vector<std::uint8_t> used(positions.size(), 0);
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const Triangle& t : triangles) {
    for (std::uint32_t v : t) {
      used[v] = 1;
      lo = glm::min(lo, positions[v]);
      hi = glm::max(hi, positions[v]);
    }
  }
  const glm::vec3 extent = hi - lo;
  const float cell = std::max({extent.x, extent.y, extent.z}) / static_cast<float>(cells);
  // (cell key, vertex), sorted: vertices of one cell become one proxy vertex.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
  keyed.reserve(positions.size());
  for (std::uint32_t v = 0; v < positions.size(); ++v) {
    if (!used[v]) continue;
    const glm::vec3 q = cell > 0.0f ? (positions[v] - lo) / cell : glm::vec3(0.0f);
    const auto ix = static_cast<std::uint64_t>(std::min(q.x, static_cast<float>(cells)));
    const auto iy = static_cast<std::uint64_t>(std::min(q.y, static_cast<float>(cells)));
    const auto iz = static_cast<std::uint64_t>(std::min(q.z, static_cast<float>(cells)));
    keyed.emplace_back((ix << 42) | (iy << 21) | iz, v);
  }
  std::sort(keyed.begin(), keyed.end());
  constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::uint32_t> proxy_of(positions.size(), kNone);
  ProxyMesh proxy;
  std::vector<float> members;
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i].first != keyed[i - 1].first) {
      proxy.positions.emplace_back(0.0f);
      members.push_back(0.0f);
    }
    proxy.positions.back() += positions[keyed[i].second];
    members.back() += 1.0f;
    proxy_of[keyed[i].second] = static_cast<std::uint32_t>(proxy.positions.size() - 1);
  }
  for (std::size_t p = 0; p < proxy.positions.size(); ++p) proxy.positions[p] /= members[p];
  for (const Triangle& t : triangles) {
    const Triangle mapped{proxy_of[t[0]], proxy_of[t[1]], proxy_of[t[2]]};
    if (mapped[0] != mapped[1] && mapped[1] != mapped[2] && mapped[0] != mapped[2]) proxy.triangles.push_back(mapped);
  }
  return proxy;
}

// The used vertices, or nothing when every vertex is used.
std::vector<glm::vec3> UsedVerticesIfAnyStray(std::span<const glm::vec3> positions,
                                              std::span<const Triangle> triangles) {
  std::vector<glm::vec3> kept;
  std::vector<std::uint8_t> used(positions.size(), 0);
  for (const Triangle& t : triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
  if (std::find(used.begin(), used.end(), 0) != used.end()) {
    for (std::size_t v = 0; v < positions.size(); ++v) {
      if (used[v]) kept.push_back(positions[v]);
    }
  }
  return kept;
}

}  // namespace

glm::vec3 Rotate(glm::vec3 v, glm::vec3 axis, float radians) {
  // Rodrigues.
  const float c = std::cos(radians), s = std::sin(radians);
  return v * c + glm::cross(axis, v) * s + axis * glm::dot(axis, v) * (1.0f - c);
}

FramingMesh PrepareFraming(const Mesh& mesh, std::size_t proxy_triangle_limit, int proxy_cells) {
  // The front-view estimate and the whole-mesh framing only need the overall
  // shape: a large mesh (a million-vertex scan) is replaced by a clustered
  // copy, so the closest-point structure stays small. Vertices no triangle
  // uses (stray points) never count.
  const std::span<const glm::vec3> positions = mesh.positions;
  const std::span<const Triangle> triangles = mesh.triangles;
  FramingMesh framing;
  ProxyMesh& proxy = framing.proxy;
  const bool use_proxy = triangles.size() > proxy_triangle_limit;
  if (use_proxy) {
    proxy = ClusterMesh(positions, triangles, proxy_cells);
    if (proxy.triangles.empty()) throw InvalidInputError("landmarks: every triangle of the mesh is degenerate");
  } else {
    proxy.positions = UsedVerticesIfAnyStray(positions, triangles);
  }
  const std::span<const glm::vec3> frame_positions =
      use_proxy ? std::span<const glm::vec3>(proxy.positions) : positions;
  const std::span<const Triangle> frame_triangles = use_proxy ? std::span<const Triangle>(proxy.triangles) : triangles;
  const ClosestPointQuery surface(Mesh{.positions = {frame_positions.begin(), frame_positions.end()},
                                       .triangles = {frame_triangles.begin(), frame_triangles.end()}});
  framing.frame = EstimateFrame(frame_positions, frame_triangles, surface);
  return framing;
}

RasterView FaceView(glm::vec3 forward, glm::vec3 up, glm::vec3 centre, float face_size, int size) {
  forward = glm::normalize(forward);
  up = glm::normalize(up - glm::dot(up, forward) * forward);
  const glm::vec3 right = glm::cross(up, forward);
  return RasterView::FromAxes(right, up, forward, centre, face_size, size, size);
}

glm::vec3 ViewAxis(const RasterView& view, int row) {
  return {view.rotation[0][row], view.rotation[1][row], view.rotation[2][row]};
}

RasterView FrontView(std::span<const glm::vec3> positions, glm::vec3 forward, glm::vec3 up, int size) {
  RasterView view = FaceView(forward, up, glm::vec3(0.0f), 1.0f, size);
  const glm::vec3 right = ViewAxis(view, 0);
  const glm::vec3 view_up = ViewAxis(view, 1);
  glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const glm::vec3& p : positions) {
    const glm::vec2 q(glm::dot(p, right), glm::dot(p, view_up));
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  const glm::vec2 mid = 0.5f * (lo + hi);
  view.centre = mid.x * right + mid.y * view_up;
  view.half_extent = 0.52f * std::max(hi.x - lo.x, hi.y - lo.y);
  return view;
}

float PixelsPerUnit(const RasterView& view) { return 0.5f * static_cast<float>(view.height) / view.half_extent; }

glm::vec3 Unproject(const RasterView& view, glm::vec2 pixel) {
  const float scale = PixelsPerUnit(view);
  const float cx = (pixel.x - 0.5f * static_cast<float>(view.width)) / scale;
  const float cy = (0.5f * static_cast<float>(view.height) - pixel.y) / scale;
  return view.centre + cx * ViewAxis(view, 0) + cy * ViewAxis(view, 1);
}

}  // namespace facerig::landmarks_detail
