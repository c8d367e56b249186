// The loops both blend paths share, so that they produce the same bits.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "facerig/runtime/rig.h"

namespace facerig::blend {

// positions[v] += w * delta (and normals[v] += w * normal delta unless
// `normals` is null) for every entry of every shape with a non-zero weight,
// in shape order.
inline void AddActiveShapes(const Rig& rig, std::span<const float> weights, glm::vec3* positions,
                            glm::vec3* normals) {
  for (std::size_t s = 0; s < weights.size(); ++s) {
    const float w = weights[s];
    if (w == 0.0f) continue;
    const BlendShapeView shape = rig.shape(s);
    const std::uint32_t* indices = shape.vertex_indices.data();
    const glm::vec3* deltas = shape.position_deltas.data();
    const std::size_t count = shape.vertex_indices.size();
    if (normals != nullptr) {
      // One pass over the entries for both, so each index is read once.
      const glm::vec3* normal_deltas = shape.normal_deltas.data();
      for (std::size_t i = 0; i < count; ++i) {
        positions[indices[i]] += w * deltas[i];
        normals[indices[i]] += w * normal_deltas[i];
      }
    } else {
      for (std::size_t i = 0; i < count; ++i) positions[indices[i]] += w * deltas[i];
    }
  }
}

// kBlendDeltas' renormalisation (a zero sum stays zero).
inline void RenormaliseBlended(glm::vec3& n) {
  const float length_sq = glm::dot(n, n);
  if (length_sq > 0.0f) n *= 1.0f / std::sqrt(length_sq);
}

// ComputeVertexNormals' normalisation of a summed normal.
inline void NormaliseSum(glm::vec3& n) {
  const float length_sq = glm::dot(n, n);
  n = length_sq > 0.0f ? n / std::sqrt(length_sq) : glm::vec3(0.0f, 0.0f, 1.0f);
}

// ComputeVertexNormals' triangle normal: twice the area, so area-weighted.
inline glm::vec3 TriangleNormal(const glm::vec3* positions, const Triangle& t) {
  return glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
}

}  // namespace facerig::blend
