// The photo fit's fallback for a template without identity modes: a smooth
// deformation of the head onto the landmarks, in the image plane.
#include <string>

#include <Eigen/Dense>
#include <glm/geometric.hpp>

#include "facerig/offline/error.h"
#include "facerig/offline/photo/fit.h"

namespace facerig {

namespace {

// The landmark vertices of a template may repeat (several dlib points on one
// vertex would make the system singular): one centre per distinct vertex.
struct Centres {
  std::vector<glm::vec3> points;
  std::vector<glm::vec3> offsets;  // world units, in the image plane
};

Centres CollectCentres(std::span<const glm::vec3> positions, std::span<const std::uint32_t> vertices,
                       std::span<const glm::vec2> pixels, const ScaledOrthoCamera& camera, int width, int height) {
  const glm::vec3 right(camera.rotation[0][0], camera.rotation[1][0], camera.rotation[2][0]);
  const glm::vec3 up(camera.rotation[0][1], camera.rotation[1][1], camera.rotation[2][1]);
  Centres centres;
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    const glm::vec3 p = positions[vertices[k]];
    bool repeated = false;
    for (const glm::vec3& q : centres.points) repeated = repeated || glm::length(q - p) < 1e-6f;
    if (repeated) continue;
    const glm::vec2 d = pixels[k] - ProjectPixel(camera, p, width, height);  // y down
    centres.points.push_back(p);
    centres.offsets.push_back((d.x * right - d.y * up) / camera.scale);
  }
  return centres;
}

}  // namespace

void RbfDeformToLandmarks(std::span<glm::vec3> positions, std::span<const std::uint32_t> vertices,
                          std::span<const glm::vec2> pixels, const ScaledOrthoCamera& camera, int width, int height) {
  if (vertices.size() != pixels.size() || vertices.size() < 4) {
    throw InvalidInputError("photo deform: need at least 4 landmark vertices and as many pixels", "landmarks");
  }
  for (const std::uint32_t v : vertices) {
    if (v >= positions.size()) throw InvalidInputError("photo deform: landmark vertex out of range", "landmarks", std::to_string(v));
  }
  const Centres centres = CollectCentres(positions, vertices, pixels, camera, width, height);
  const auto n = static_cast<Eigen::Index>(centres.points.size());
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(n + 4, n + 4);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n + 4, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const glm::vec3 pi = centres.points[static_cast<std::size_t>(i)];
    for (Eigen::Index j = 0; j < n; ++j) system(i, j) = glm::length(pi - centres.points[static_cast<std::size_t>(j)]);
    const Eigen::Vector4d affine(pi.x, pi.y, pi.z, 1.0);
    system.block(i, n, 1, 4) = affine.transpose();
    system.block(n, i, 4, 1) = affine;
    const glm::vec3 o = centres.offsets[static_cast<std::size_t>(i)];
    rhs.row(i) = Eigen::RowVector3d(o.x, o.y, o.z);
  }
  // Few or coplanar centres leave the affine part underdetermined: least squares.
  const Eigen::MatrixXd coefficients = system.completeOrthogonalDecomposition().solve(rhs);
  std::vector<glm::vec3> moved(positions.begin(), positions.end());
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const glm::vec3 p = positions[v];
    Eigen::RowVector3d offset = Eigen::RowVector3d(p.x, p.y, p.z) * coefficients.block(n, 0, 3, 3) + coefficients.row(n + 3);
    for (Eigen::Index i = 0; i < n; ++i) {
      offset += glm::length(p - centres.points[static_cast<std::size_t>(i)]) * coefficients.row(i);
    }
    moved[v] = p + glm::vec3(static_cast<float>(offset[0]), static_cast<float>(offset[1]), static_cast<float>(offset[2]));
  }
  std::copy(moved.begin(), moved.end(), positions.begin());
}

}  // namespace facerig
