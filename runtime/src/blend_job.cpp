#include "facerig/runtime/blend_job.h"

#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>

#include "facerig/runtime/rig_builder.h"

namespace facerig {

const char* ToString(BlendJobError error) {
  switch (error) {
    case BlendJobError::kNone: return "no error";
    case BlendJobError::kNoRig: return "no rig";
    case BlendJobError::kWeightCountMismatch: return "weight count differs from the rig's shape count";
    case BlendJobError::kNonFiniteWeight: return "a weight is NaN or infinite";
    case BlendJobError::kPositionsTooSmall: return "out_positions size differs from the vertex count";
    case BlendJobError::kNormalsTooSmall: return "out_normals size differs from the vertex count";
    case BlendJobError::kRigHasNoNormalDeltas: return "kBlendDeltas on a rig without normal deltas";
  }
  return "unknown error";
}

BlendJobError BlendJob::Validate() const {
  if (rig == nullptr) return BlendJobError::kNoRig;
  if (weights.size() != rig->shape_count()) return BlendJobError::kWeightCountMismatch;
  for (float w : weights) {
    if (!std::isfinite(w)) return BlendJobError::kNonFiniteWeight;
  }
  if (out_positions.size() != rig->vertex_count()) return BlendJobError::kPositionsTooSmall;
  if (normal_mode != NormalMode::kNone && out_normals.size() != rig->vertex_count()) {
    return BlendJobError::kNormalsTooSmall;
  }
  if (normal_mode == NormalMode::kBlendDeltas && !rig->has_normal_deltas()) {
    return BlendJobError::kRigHasNoNormalDeltas;
  }
  return BlendJobError::kNone;
}

BlendJobError BlendJob::Run() const {
  if (const BlendJobError error = Validate(); error != BlendJobError::kNone) return error;
  const std::span<const glm::vec3> neutral = rig->positions();
  std::memcpy(out_positions.data(), neutral.data(), neutral.size_bytes());
  const bool blend_normals = normal_mode == NormalMode::kBlendDeltas;
  if (blend_normals) {
    std::memcpy(out_normals.data(), rig->normals().data(), rig->normals().size_bytes());
  }

  glm::vec3* positions = out_positions.data();
  glm::vec3* normals = out_normals.data();
  for (std::size_t s = 0; s < weights.size(); ++s) {
    const float w = weights[s];
    if (w == 0.0f) continue;
    const BlendShapeView shape = rig->shape(s);
    const std::uint32_t* indices = shape.vertex_indices.data();
    const glm::vec3* deltas = shape.position_deltas.data();
    const std::size_t count = shape.vertex_indices.size();
    if (blend_normals) {
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

  if (blend_normals) {
    for (glm::vec3& n : out_normals) {
      const float length_sq = glm::dot(n, n);
      if (length_sq > 0.0f) n *= 1.0f / std::sqrt(length_sq);
    }
  } else if (normal_mode == NormalMode::kRecompute) {
    ComputeVertexNormals(out_positions, rig->triangles(), out_normals);
  }
  return BlendJobError::kNone;
}

}  // namespace facerig
