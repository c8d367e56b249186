// Closest point on a triangle mesh: a bounding-volume hierarchy over the
// triangles, queried for the nearest surface point with its triangle id and
// barycentrics. Used by rigid alignment (ICP) and non-rigid ICP.
//
// Positions in the mesh's own units. Degenerate triangles are kept (their
// closest point is still well defined); the mesh may have several parts and
// holes. Boundary edges (used by one triangle only) are recorded so callers
// can reject correspondences that land on the border of a scan.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"

namespace facerig {

struct ClosestPointHit {
  std::int32_t triangle = -1;  // -1: nothing within the search radius
  glm::vec3 barycentrics{0.0f};  // weights of the triangle's vertices 0, 1, 2
  glm::vec3 point{0.0f};
  glm::vec3 normal{0.0f};  // unit face normal of the triangle (0 when degenerate)
  float distance = std::numeric_limits<float>::infinity();
  // The point lies on a boundary edge or boundary vertex of the mesh.
  bool on_boundary = false;
};

class ClosestPointQuery {
 public:
  // Copies the mesh. Throws InvalidInputError on an empty mesh, a vertex index
  // out of range or a non-finite position.
  explicit ClosestPointQuery(const Mesh& mesh);

  // The nearest surface point within `max_distance` (hit.triangle == -1 when none).
  ClosestPointHit Find(glm::vec3 query,
                       float max_distance = std::numeric_limits<float>::infinity()) const;
  // The nearest point on triangles facing the same way as `normal` (unit face
  // normal . normal >= min_normal_dot), so a point on the lower lip does not
  // snap onto the upper lip resting on it. Degenerate triangles never qualify.
  ClosestPointHit FindFacing(glm::vec3 query, glm::vec3 normal, float min_normal_dot,
                             float max_distance = std::numeric_limits<float>::infinity()) const;

  std::span<const glm::vec3> positions() const { return positions_; }
  std::span<const Triangle> triangles() const { return triangles_; }
  // Area-weighted unit vertex normals of the mesh.
  std::span<const glm::vec3> vertex_normals() const { return vertex_normals_; }

 private:
  struct Node {
    glm::vec3 lo, hi;
    std::uint32_t first = 0;  // leaf: first index into order_; inner: left child
    std::uint32_t count = 0;  // leaf: triangle count; inner: 0 (right child = left + 1)
  };
  void CheckMesh() const;  // throws InvalidInputError
  void ComputeNormals();
  void FindBoundaryEdges();
  void BuildTree();
  void Build(std::uint32_t count, const std::vector<glm::vec3>& centroids);
  ClosestPointHit FindFiltered(glm::vec3 query, float max_distance, const glm::vec3* normal,
                               float min_normal_dot) const;

  std::vector<glm::vec3> positions_;
  std::vector<Triangle> triangles_;
  std::vector<glm::vec3> vertex_normals_;
  std::vector<glm::vec3> face_normals_;
  std::vector<std::uint8_t> boundary_edges_;  // per triangle: bit e = edge (v_e, v_e+1)
  std::vector<std::uint8_t> boundary_vertex_;
  std::vector<std::uint32_t> order_;
  std::vector<Node> nodes_;
  std::vector<glm::vec3> triangle_boxes_;  // lo, hi per triangle; only during the build
};

// Closest point on one triangle (Ericson, Real-Time Collision Detection 5.1.5).
// Returns the point; `barycentrics` gets its weights.
glm::vec3 ClosestPointOnTriangle(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c,
                                 glm::vec3& barycentrics);

}  // namespace facerig
