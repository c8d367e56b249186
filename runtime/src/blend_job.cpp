#include "facerig/runtime/blend_job.h"

#include <cmath>
#include <cstring>

#include "blend_kernels.h"
#include "facerig/runtime/blend_plan.h"
#include "facerig/runtime/rig_builder.h"
#include "sparse_blend.h"

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
    case BlendJobError::kStateForAnotherRig: return "the blend state's plan was built for another rig";
    case BlendJobError::kModeNeedsState: return "kBlendRecomputedDeltas needs a blend state";
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
  if (state != nullptr && &state->plan().rig() != rig) return BlendJobError::kStateForAnotherRig;
  if (normal_mode == NormalMode::kBlendRecomputedDeltas && state == nullptr) return BlendJobError::kModeNeedsState;
  return BlendJobError::kNone;
}

BlendJobError BlendJob::Run() const {
  if (const BlendJobError error = Validate(); error != BlendJobError::kNone) return error;
  if (state != nullptr) {
    const CrowdMember one{weights, out_positions, out_normals, state};
    SparseBlend::Run(*rig, normal_mode, std::span(&one, 1));
    return BlendJobError::kNone;
  }
  // Every vertex: the neutral, plus the active shapes, then the normals of all.
  const std::span<const glm::vec3> neutral = rig->positions();
  std::memcpy(out_positions.data(), neutral.data(), neutral.size_bytes());
  const bool blend_normals = normal_mode == NormalMode::kBlendDeltas;
  if (blend_normals) {
    std::memcpy(out_normals.data(), rig->normals().data(), rig->normals().size_bytes());
  }
  blend::AddActiveShapes(*rig, weights, out_positions.data(), blend_normals ? out_normals.data() : nullptr);
  if (blend_normals) {
    for (glm::vec3& n : out_normals) blend::RenormaliseBlended(n);
  } else if (normal_mode == NormalMode::kRecompute) {
    ComputeVertexNormals(out_positions, rig->triangles(), out_normals);
  }
  return BlendJobError::kNone;
}

}  // namespace facerig
