#include "support/registration_targets.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>

#include <Eigen/Geometry>
#include <glm/geometric.hpp>

#include "facerig/offline/closest_point.h"
#include "facerig/offline/nonrigid_icp.h"
#include "facerig/runtime/io/obj.h"
#include "support/test_meshes.h"

namespace facerig::test {

const IctFaceModel& IctFaces() {
  static const IctFaceModel model = [] {
    IctFaceModel m;
    ObjMesh neutral = ReadObj(IctDir() / "generic_neutral_mesh.obj");
    m.neutral = std::move(neutral.positions);
    m.triangles = std::move(neutral.triangles);
    for (int i = 0; i < 20; ++i) {
      char name[32];
      std::snprintf(name, sizeof(name), "identity%03d.obj", i);
      m.identities.push_back(ReadObj(IctDir() / name).positions);
    }
    for (const Triangle& t : m.triangles) {
      if (t[0] < kIctHeadVertexCount && t[1] < kIctHeadVertexCount && t[2] < kIctHeadVertexCount) {
        m.head_triangles.push_back(t);
      }
    }
    return m;
  }();
  return model;
}

std::vector<glm::vec3> RandomIctFace(std::uint32_t seed, double sigma) {
  const IctFaceModel& model = IctFaces();
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

// 1-to-4 midpoint subdivision.
void Subdivide(std::vector<glm::vec3>& positions, std::vector<Triangle>& triangles) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
  auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
    const auto key = std::make_pair(std::min(a, b), std::max(a, b));
    const auto it = midpoints.find(key);
    if (it != midpoints.end()) return it->second;
    const auto index = static_cast<std::uint32_t>(positions.size());
    positions.push_back(0.5f * (positions[a] + positions[b]));
    midpoints.emplace(key, index);
    return index;
  };
  std::vector<Triangle> out;
  out.reserve(triangles.size() * 4);
  for (const Triangle& t : triangles) {
    const std::uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
    out.push_back({t[0], ab, ca});
    out.push_back({ab, t[1], bc});
    out.push_back({ca, bc, t[2]});
    out.push_back({ab, bc, ca});
  }
  triangles = std::move(out);
}

}  // namespace

RegistrationTarget MakeRegistrationTarget(const RegistrationTargetOptions& options) {
  const IctFaceModel& model = IctFaces();
  RegistrationTarget target;
  const std::vector<glm::vec3> face = RandomIctFace(options.seed, options.identity_sigma);
  std::mt19937 rng(options.seed * 7919u + 17u);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);

  // Geometry in ICT centimetres first.
  std::vector<glm::vec3> positions(face.begin(), face.begin() + kIctHeadVertexCount);
  std::vector<Triangle> triangles = model.head_triangles;
  if (options.remesh) {
    const ClosestPointQuery surface(positions, triangles);
    Subdivide(positions, triangles);
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
  for (std::uint32_t v : IctLandmarkVertices()) target.true_landmarks.push_back(target.true_ict_positions[v]);
  return target;
}

}  // namespace facerig::test
