// Many characters on one rig in one job: CrowdBlendJob blends them tile by
// tile of the mesh, every character's share of a tile before the next tile,
// so that the tile's shape deltas are read from the cache by all of them. The
// outputs are each character's own BlendJob with its BlendState, bit for bit
// (BlendJob with a state is a crowd of one). Like BlendJob it allocates
// nothing, throws nothing and takes no lock; one job per thread, over
// different characters.
#pragma once

#include <cstddef>
#include <span>

#include <glm/vec3.hpp>

#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/rig.h"

namespace facerig {

class BlendState;

struct CrowdMember {
  std::span<const float> weights;  // one per rig shape, as BlendJob's
  std::span<glm::vec3> out_positions;
  std::span<glm::vec3> out_normals;  // may be empty with kNone
  BlendState* state = nullptr;       // required; each member its own, with its own buffers
};

struct CrowdBlendJob {
  const Rig* rig = nullptr;
  NormalMode normal_mode = NormalMode::kNone;
  std::span<const CrowdMember> members;

  // Checks every member as BlendJob::Validate does (and that it has a state);
  // `failed` (optional) gets the first failing member's index.
  BlendJobError Validate(std::size_t* failed = nullptr) const;
  // Validates, then blends. On error nothing is written.
  BlendJobError Run(std::size_t* failed = nullptr) const;
};

}  // namespace facerig
