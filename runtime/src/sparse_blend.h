// The blend with BlendStates (blend_plan.h): writes only what moved, tile by
// tile of the mesh across a crowd's members. BlendJob with a state runs it
// for a crowd of one.
#pragma once

#include <span>

#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/crowd_blend_job.h"

namespace facerig {

class SparseBlend {
 public:
  // The members are valid (CrowdBlendJob::Validate), each with its own state.
  static void Run(const Rig& rig, NormalMode mode, std::span<const CrowdMember> members);

 private:
  static void Prepare(const Rig& rig, NormalMode mode, const CrowdMember& member);
  static void PositionsTile(const Rig& rig, const CrowdMember& member, std::size_t tile);
  static void NormalsTile(const Rig& rig, NormalMode mode, const CrowdMember& member, std::size_t tile);
  static void Finish(const Rig& rig, NormalMode mode, const CrowdMember& member);
};

}  // namespace facerig
