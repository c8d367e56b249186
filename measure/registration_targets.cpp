#include "measure/registration_targets.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <string>

#include <Eigen/Geometry>
#include <glm/geometric.hpp>

#include "facerig/offline/geometry/closest_point.h"
#include "facerig/offline/error.h"
#include "facerig/offline/registration/nonrigid_icp.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/rig_builder.h"
#include "measure/expression_error.h"

namespace facerig::test {

FaceTemplateInfo LoadIctTemplateInfo(const Rig& rig) {
  for (const std::filesystem::path& dir : ShippedTemplateDirectories()) {
    const std::filesystem::path path = dir / "ict-facekit.template.json";
    if (std::filesystem::is_regular_file(path)) return LoadFaceTemplateInfo(path, rig);
  }
  throw IoError(IoErrorKind::kOpenFailed, "ict-facekit.template.json", "not found in the shipped template folders");
}

IctFaceModel LoadIctFaces(const std::filesystem::path& ict_dir) {
  IctFaceModel m;
  RawRig neutral = ToRawRig(ReadObj(ict_dir / "generic_neutral_mesh.obj"));
  m.neutral = std::move(neutral.positions);
  m.triangles = std::move(neutral.triangles);
  {
    // The descriptor validates against (and fingerprints) the neutral.
    RawRig raw;
    raw.positions = m.neutral;
    raw.triangles = m.triangles;
    std::string problem;
    const std::optional<Rig> rig = RigBuilder::Build(raw, &problem);
    if (!rig) throw IoError(IoErrorKind::kParse, (ict_dir / "generic_neutral_mesh.obj").string(), problem);
    m.info = LoadIctTemplateInfo(*rig);
  }
  for (int i = 0; i < 20; ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "identity%03d.obj", i);
    m.identities.push_back(ReadObj(ict_dir / name).positions);
    if (m.identities.back().size() != m.neutral.size()) {
      throw IoError(IoErrorKind::kTopologyMismatch, (ict_dir / name).string(),
                    "has " + std::to_string(m.identities.back().size()) + " vertices, the neutral " +
                        std::to_string(m.neutral.size()));
    }
  }
  const std::uint32_t head = m.head_vertex_count();
  for (const Triangle& t : m.triangles) {
    if (t[0] < head && t[1] < head && t[2] < head) {
      m.head_triangles.push_back(t);
    }
  }
  return m;
}

std::vector<glm::vec3> RandomIctFace(const IctFaceModel& model, std::uint32_t seed, double sigma) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, sigma);
  std::vector<glm::vec3> face = model.neutral;
  for (const auto& identity : model.identities) {
    const auto w = static_cast<float>(normal(rng));
    for (std::size_t v = 0; v < face.size(); ++v) face[v] += w * (identity[v] - model.neutral[v]);
  }
  return face;
}

namespace {

std::uint64_t EdgeKey(std::uint32_t a, std::uint32_t b) {
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
}

// Sorted unique undirected edges.
std::vector<std::uint64_t> UniqueEdges(const std::vector<Triangle>& triangles) {
  std::vector<std::uint64_t> keys;
  keys.reserve(3 * triangles.size());
  for (const Triangle& t : triangles) {
    for (std::size_t e = 0; e < 3; ++e) keys.push_back(EdgeKey(t[e], t[(e + 1) % 3]));
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

// Midpoint subdivision of the edges marked in `split` (parallel to `edges`,
// the sorted unique edges). Each triangle is cut along its split edges: into
// 4 (all three: the classic 1-to-4), 3 (two: the quad cut along its shorter
// diagonal) or 2 (one). Midpoints are numbered in the order the triangles
// first meet them, so splitting every edge gives the plain 1-to-4 scheme.
void SplitEdges(std::vector<glm::vec3>& positions, std::vector<Triangle>& triangles,
                const std::vector<std::uint64_t>& edges, const std::vector<std::uint8_t>& split) {
  constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::uint32_t> midpoint_of(edges.size(), kNone);
  auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
    const auto slot = static_cast<std::size_t>(
        std::lower_bound(edges.begin(), edges.end(), EdgeKey(a, b)) - edges.begin());
    if (!split[slot]) return kNone;
    if (midpoint_of[slot] == kNone) {
      midpoint_of[slot] = static_cast<std::uint32_t>(positions.size());
      positions.push_back(0.5f * (positions[a] + positions[b]));
    }
    return midpoint_of[slot];
  };
  std::vector<Triangle> out;
  out.reserve(triangles.size() * 4);
  for (const Triangle& t : triangles) {
    const std::uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
    const int count = (ab != kNone ? 1 : 0) + (bc != kNone ? 1 : 0) + (ca != kNone ? 1 : 0);
    if (count == 3) {
      out.push_back({t[0], ab, ca});
      out.push_back({ab, t[1], bc});
      out.push_back({ca, bc, t[2]});
      out.push_back({ab, bc, ca});
      continue;
    }
    if (count == 0) {
      out.push_back(t);
      continue;
    }
    // Rotate (keeping the winding) so that edge (v0, v1) is split and, with
    // two splits, edge (v1, v2) too.
    std::array<std::uint32_t, 3> v{t[0], t[1], t[2]};
    std::array<std::uint32_t, 3> m{ab, bc, ca};  // m[e]: midpoint of (v[e], v[e + 1])
    for (int turn = 0; turn < 3; ++turn) {
      if (count == 1 ? m[0] != kNone : (m[0] != kNone && m[1] != kNone)) break;
      std::rotate(v.begin(), v.begin() + 1, v.end());
      std::rotate(m.begin(), m.begin() + 1, m.end());
    }
    if (count == 1) {
      out.push_back({v[0], m[0], v[2]});
      out.push_back({m[0], v[1], v[2]});
    } else {
      out.push_back({m[0], v[1], m[1]});
      // The quad v0, m0, m1, v2: cut along its shorter diagonal.
      if (glm::length(positions[v[0]] - positions[m[1]]) <= glm::length(positions[m[0]] - positions[v[2]])) {
        out.push_back({v[0], m[0], m[1]});
        out.push_back({v[0], m[1], v[2]});
      } else {
        out.push_back({v[0], m[0], v[2]});
        out.push_back({m[0], m[1], v[2]});
      }
    }
  }
  triangles = std::move(out);
}

// See RegistrationTargetOptions::target_vertex_count.
void Remesh(std::vector<glm::vec3>& positions, std::vector<Triangle>& triangles, std::size_t target_count) {
  for (bool first = true;; first = false) {
    const std::vector<std::uint64_t> edges = UniqueEdges(triangles);
    const bool full = target_count == 0 ? first : positions.size() + edges.size() <= target_count;
    if (full) {
      SplitEdges(positions, triangles, edges, std::vector<std::uint8_t>(edges.size(), 1));
      continue;
    }
    if (target_count <= positions.size()) return;
    // Split the longest edges, as many as vertices are missing.
    const std::size_t missing = target_count - positions.size();
    std::vector<float> length(edges.size());
    for (std::size_t e = 0; e < edges.size(); ++e) {
      const auto a = static_cast<std::uint32_t>(edges[e] >> 32), b = static_cast<std::uint32_t>(edges[e]);
      length[e] = glm::length(positions[a] - positions[b]);
    }
    std::vector<std::uint32_t> order(edges.size());
    for (std::size_t e = 0; e < order.size(); ++e) order[e] = static_cast<std::uint32_t>(e);
    std::nth_element(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(missing - 1), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) {
                       return length[a] > length[b] || (length[a] == length[b] && a < b);
                     });
    std::vector<std::uint8_t> split(edges.size(), 0);
    for (std::size_t k = 0; k < missing; ++k) split[order[k]] = 1;
    SplitEdges(positions, triangles, edges, split);
    return;
  }
}

}  // namespace

RegistrationTarget MakeRegistrationTarget(const IctFaceModel& model, const RegistrationTargetOptions& options) {
  RegistrationTarget target;
  const std::vector<glm::vec3> face = RandomIctFace(model, options.seed, options.identity_sigma);
  std::mt19937 rng(options.seed * 7919u + 17u);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);

  // Geometry in ICT centimetres first.
  std::vector<glm::vec3> positions(face.begin(), face.begin() + model.head_vertex_count());
  std::vector<Triangle> triangles = model.head_triangles;
  if (options.remesh) {
    const ClosestPointQuery surface(Mesh{.positions = positions, .triangles = triangles});
    Remesh(positions, triangles, options.target_vertex_count);
    // Jitter every vertex along the surface by up to a third of the local edge
    // length and project it back: no target vertex sits on an ICT vertex.
    std::vector<float> edge(positions.size(), 0.0f);
    for (const Triangle& t : triangles) {
      for (std::size_t e = 0; e < 3; ++e) {
        const float length = glm::length(positions[t[e]] - positions[t[(e + 1) % 3]]);
        edge[t[e]] = std::max(edge[t[e]], length);
      }
    }
    std::vector<glm::vec3> normals(positions.size(), glm::vec3(0.0f));
    for (const Triangle& t : triangles) {
      const glm::vec3 nrm = glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
      for (std::uint32_t v : t) normals[v] += nrm;
    }
    for (std::size_t v = 0; v < positions.size(); ++v) {
      glm::vec3 offset(static_cast<float>(uniform(rng)), static_cast<float>(uniform(rng)),
                       static_cast<float>(uniform(rng)));
      const float length = glm::length(normals[v]);
      if (length > 0.0f) {
        const glm::vec3 nrm = normals[v] / length;
        offset -= glm::dot(offset, nrm) * nrm;  // tangential
      }
      positions[v] = surface.Find(positions[v] + offset * (edge[v] / 3.0f)).point;
    }
  }

  // Random similarity: rotation about a random axis by up to the limit.
  glm::vec3 axis(static_cast<float>(uniform(rng)), static_cast<float>(uniform(rng)),
                 static_cast<float>(uniform(rng)));
  axis = glm::length(axis) > 1e-3f ? glm::normalize(axis) : glm::vec3(0, 1, 0);
  target.rotation_degrees = options.max_rotation_degrees * std::abs(uniform(rng));
  const double angle = target.rotation_degrees * 3.14159265358979323846 / 180.0;
  target.units_per_cm = options.units_per_cm;
  if (target.units_per_cm <= 0.0) {
    static constexpr double kUnits[3] = {0.01, 1.0, 10.0};
    target.units_per_cm = kUnits[static_cast<std::size_t>(rng() % 3)];
  }
  target.from_ict.scale = target.units_per_cm;
  target.from_ict.rotation =
      Eigen::AngleAxisd(angle, Eigen::Vector3d(axis.x, axis.y, axis.z)).toRotationMatrix();
  target.from_ict.translation =
      Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng)) * 50.0 * target.units_per_cm;

  target.positions.reserve(positions.size());
  for (const glm::vec3& p : positions) target.positions.push_back(target.from_ict.Apply(p));
  target.triangles = std::move(triangles);
  target.true_ict_positions.reserve(face.size());
  for (const glm::vec3& p : face) target.true_ict_positions.push_back(target.from_ict.Apply(p));
  for (std::uint32_t v : model.info.landmark_vertices) target.true_landmarks.push_back(target.true_ict_positions[v]);
  return target;
}

}  // namespace facerig::test

namespace facerig::test {

BuiltRigErrors MeasureBuiltRig(const IctFaceModel& model, const Rig& template_rig, const RegistrationTarget& target,
                               const Rig& built) {
  const ClosestPointQuery truth_surface(Mesh{.positions = target.true_ict_positions, .triangles = model.head_triangles});
  std::vector<std::uint32_t> face_vertices;  // target vertices on the face region
  std::vector<ClosestPointHit> material;
  for (std::uint32_t v = 0; v < target.positions.size(); ++v) {
    const ClosestPointHit hit = truth_surface.Find(target.positions[v]);
    const Triangle& t = model.head_triangles[static_cast<std::size_t>(hit.triangle)];
    const std::uint32_t face = model.face_vertex_count();
    if (t[0] < face && t[1] < face && t[2] < face) {
      face_vertices.push_back(v);
      material.push_back(hit);
    }
  }
  const std::size_t n = face_vertices.size();
  std::vector<glm::vec3> rest(n), truth(n), result(n), true_delta(template_rig.vertex_count());
  std::vector<glm::vec3> built_delta(built.vertex_count());
  BuiltRigErrors errors;
  errors.face_vertices = n;
  for (std::size_t s = 0; s < template_rig.shape_count(); ++s) {
    std::fill(true_delta.begin(), true_delta.end(), glm::vec3(0.0f));
    const BlendShapeView shape = template_rig.shape(s);
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      true_delta[shape.vertex_indices[i]] =
          static_cast<float>(target.from_ict.scale) * target.from_ict.ApplyToDirection(shape.position_deltas[i]);
    }
    const std::optional<std::size_t> built_shape = built.FindShape(shape.name);
    if (!built_shape) throw InvalidInputError("the built rig has no shape '" + std::string(shape.name) + "'");
    std::fill(built_delta.begin(), built_delta.end(), glm::vec3(0.0f));
    const BlendShapeView mapped = built.shape(*built_shape);
    for (std::size_t i = 0; i < mapped.vertex_indices.size(); ++i) {
      built_delta[mapped.vertex_indices[i]] = mapped.position_deltas[i];
    }
    for (std::size_t i = 0; i < n; ++i) {
      const Triangle& t = model.head_triangles[static_cast<std::size_t>(material[i].triangle)];
      const glm::vec3 b = material[i].barycentrics;
      rest[i] = material[i].point;
      truth[i] = rest[i] + b.x * true_delta[t[0]] + b.y * true_delta[t[1]] + b.z * true_delta[t[2]];
      result[i] = target.positions[face_vertices[i]] + built_delta[face_vertices[i]];
    }
    const ExpressionError error = MeasureExpressionError(rest, truth, result, 0, n);
    errors.names.emplace_back(shape.name);
    errors.relative.push_back(error.relative_error);
    errors.leak.push_back(error.leak);
  }
  return errors;
}

}  // namespace facerig::test
