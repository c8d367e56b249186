// Moving a mesh's vertex data by affine transforms (a node's world transform,
// or per vertex a skin's blended joint matrix): positions, normals, and the
// morph targets' position and normal deltas. Private to facerig::runtime_io.
#pragma once

#include <cmath>
#include <cstdint>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "facerig/runtime/rig_builder.h"

namespace facerig::gltf_internal {

// One affine transform as it applies to each kind of vertex data. Normals go
// by the cofactor matrix (the inverse transpose up to a positive factor, and
// defined for a singular transform too), so that a transform that flattens
// the mesh (a scale of 0) moves nothing to NaN: a normal it cannot carry is kept.
class VertexMover {
 public:
  explicit VertexMover(const glm::dmat4& transform) : transform_(transform), linear_(transform) {
    const glm::dvec3 a = linear_[0], b = linear_[1], c = linear_[2];
    const double det = glm::dot(a, glm::cross(b, c));
    normal_ = glm::dmat3(glm::cross(b, c), glm::cross(c, a), glm::cross(a, b)) * (det < 0.0 ? -1.0 : 1.0);
  }

  glm::vec3 Position(glm::vec3 p) const { return glm::vec3(transform_ * glm::dvec4(p, 1.0)); }
  glm::vec3 Delta(glm::vec3 d) const { return glm::vec3(linear_ * glm::dvec3(d)); }
  glm::vec3 Normal(glm::vec3 n) const {
    const glm::dvec3 moved = normal_ * glm::dvec3(n);
    const double length = glm::length(moved);
    return length > 1e-300 && std::isfinite(length) ? glm::vec3(moved / length) : n;
  }
  // A normal delta stays the change of a unit normal: Normal(n + d) - Normal(n).
  glm::vec3 NormalDelta(glm::vec3 n, glm::vec3 d) const { return Normal(n + d) - Normal(n); }

 private:
  glm::dmat4 transform_;
  glm::dmat3 linear_;
  glm::dmat3 normal_;
};

// Moves every vertex v of `piece` (and its shapes' deltas) by
// transform_of(v), a glm::dmat4; vertices whose transform is the identity
// are left exactly as they are. Normal deltas need the rest normals: without
// them (a piece without normals) they are moved as directions.
template <typename TransformOf>
void MoveVertices(const TransformOf& transform_of, RawRig* piece) {
  const bool with_normals = piece->normals.size() == piece->positions.size();
  for (RawBlendShape& shape : piece->shapes) {
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      const std::uint32_t v = shape.vertex_indices[i];
      const glm::dmat4 transform = transform_of(v);
      if (transform == glm::dmat4(1.0)) continue;  // bit for bit as read
      const VertexMover mover(transform);
      shape.position_deltas[i] = mover.Delta(shape.position_deltas[i]);
      if (i >= shape.normal_deltas.size()) continue;
      const glm::vec3 d = shape.normal_deltas[i];
      shape.normal_deltas[i] = with_normals ? mover.NormalDelta(piece->normals[v], d) : mover.Normal(d) * glm::length(d);
    }
  }
  for (std::size_t v = 0; v < piece->positions.size(); ++v) {
    const glm::dmat4 transform = transform_of(static_cast<std::uint32_t>(v));
    if (transform == glm::dmat4(1.0)) continue;
    const VertexMover mover(transform);
    piece->positions[v] = mover.Position(piece->positions[v]);
    if (with_normals) piece->normals[v] = mover.Normal(piece->normals[v]);
  }
}

}  // namespace facerig::gltf_internal
