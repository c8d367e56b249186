#include "facerig/runtime/crowd_blend_job.h"

#include "facerig/runtime/blend_plan.h"
#include "sparse_blend.h"

namespace facerig {

BlendJobError CrowdBlendJob::Validate(std::size_t* failed) const {
  for (std::size_t i = 0; i < members.size(); ++i) {
    const CrowdMember& member = members[i];
    const BlendJob job{rig, member.weights, normal_mode, member.out_positions, member.out_normals, member.state};
    BlendJobError error = job.Validate();
    if (error == BlendJobError::kNone && member.state == nullptr) error = BlendJobError::kModeNeedsState;
    if (error != BlendJobError::kNone) {
      if (failed != nullptr) *failed = i;
      return error;
    }
  }
  return BlendJobError::kNone;
}

BlendJobError CrowdBlendJob::Run(std::size_t* failed) const {
  if (const BlendJobError error = Validate(failed); error != BlendJobError::kNone) return error;
  SparseBlend::Run(*rig, normal_mode, members);
  return BlendJobError::kNone;
}

}  // namespace facerig
