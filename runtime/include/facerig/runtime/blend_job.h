// Per-frame sparse blend-shape evaluation:
//   positions = neutral + sum_i w_i * delta_i   over the shapes with w_i != 0.
//
// The job owns no memory: the caller sizes the outputs once (vertex_count()
// elements each). Run() allocates nothing, throws nothing and takes no lock,
// so one job per character may run on many threads at once over one shared Rig.
//
// Without a state, Run writes every vertex (and kRecompute walks every
// triangle): for one-off blends. With a BlendState (blend_plan.h), kept per
// character with its output buffers, Run writes only what moved since the
// previous frame; the outputs are the same, bit for bit.
#pragma once

#include <cstdint>
#include <span>

#include <glm/vec3.hpp>

#include "facerig/runtime/rig.h"

namespace facerig {

class BlendState;

enum class NormalMode : std::uint8_t {
  kNone,           // positions only; out_normals is ignored (may be empty)
  kBlendDeltas,    // neutral normal + sum_i w_i * normal_delta_i, renormalised
                   // (needs rig.has_normal_deltas())
  kRecompute,      // area-weighted normals recomputed from the blended positions
  kBlendRecomputedDeltas,  // kRecompute's normals from each shape's precomputed
                           // change of them (blend_plan.h): within a degree of
                           // kRecompute where the surface is smooth, at a fraction
                           // of its cost; needs a state (the plan holds the changes)
};

enum class BlendJobError : std::uint8_t {
  kNone,
  kNoRig,
  kWeightCountMismatch,  // weights.size() != rig->shape_count()
  kNonFiniteWeight,
  kPositionsTooSmall,    // out_positions.size() != vertex_count()
  kNormalsTooSmall,      // out_normals.size() != vertex_count() with a normal mode
  kRigHasNoNormalDeltas, // kBlendDeltas on a rig without normal deltas
  kStateForAnotherRig,   // the state's plan was built for another rig
  kModeNeedsState,       // kBlendRecomputedDeltas without a state (or a crowd member without one)
};

const char* ToString(BlendJobError error);

struct BlendJob {
  const Rig* rig = nullptr;
  // One weight per rig shape (dense, indexed like rig->shape(i)); zeros are
  // skipped, so a speech frame with 12 of 53 active pays for 12. Usually in
  // [0,1]; any finite value is accepted (negative and >1 extrapolate).
  std::span<const float> weights;
  NormalMode normal_mode = NormalMode::kNone;
  std::span<glm::vec3> out_positions;
  std::span<glm::vec3> out_normals;
  // Optional, per character: what the previous Run left in these outputs.
  BlendState* state = nullptr;

  // Checks the inputs without touching the outputs.
  BlendJobError Validate() const;
  // Validates, then evaluates. Returns kNone on success; on error the
  // outputs are left untouched.
  BlendJobError Run() const;
};

}  // namespace facerig
