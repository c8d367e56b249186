// Per-frame blending into the caller's buffers (BlendJob): no allocation.
// fr_rig_blend writes every vertex; a blender (a BlendState per pair of
// buffers) only what moved.
#include <memory>
#include <span>

#include <glm/vec3.hpp>

#include "boundary.h"
#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/blend_plan.h"
#include "handles.h"

static_assert(sizeof(glm::vec3) == 3 * sizeof(float) && alignof(glm::vec3) == alignof(float),
              "caller float triples are read as glm::vec3");
static_assert(static_cast<int>(facerig::NormalMode::kBlendRecomputedDeltas) == FR_NORMALS_BLEND_RECOMPUTED,
              "fr_normal_mode values are NormalMode's");

using namespace facerig::capi;

namespace {

// Both calls' checks and the blend; `state` may be null (every vertex).
fr_status Blend(const facerig::Rig& r, facerig::BlendState* state, const float* weights, size_t weight_count,
                fr_normal_mode mode, float* positions, float* normals, size_t vertex_capacity) {
  if (mode != FR_NORMALS_NONE && mode != FR_NORMALS_BLEND_DELTAS && mode != FR_NORMALS_RECOMPUTE &&
      mode != FR_NORMALS_BLEND_RECOMPUTED) {
    return Fail(FR_ERROR_INVALID_ARGUMENT, "mode is not an fr_normal_mode");
  }
  if (mode == FR_NORMALS_BLEND_RECOMPUTED && state == nullptr) {
    return Fail(FR_ERROR_INVALID_ARGUMENT, "FR_NORMALS_BLEND_RECOMPUTED needs a blender (fr_blender_blend)");
  }
  if (weights == nullptr && weight_count > 0) return Fail(FR_ERROR_INVALID_ARGUMENT, "weights is NULL");
  FR_REQUIRE(positions, "positions");
  if (weight_count != r.shape_count()) {
    char given[24], count[24];
    return Fail(FR_ERROR_INVALID_ARGUMENT, {"weight_count is ", Number(weight_count, given),
                                            ", the rig has ", Number(r.shape_count(), count), " shapes"});
  }
  if (mode != FR_NORMALS_NONE) FR_REQUIRE(normals, "normals");
  if (const fr_status s = CheckCapacity(r.vertex_count(), vertex_capacity, nullptr, "vertices"); s != FR_OK) {
    return s;
  }
  facerig::BlendJob job;
  job.rig = &r;
  job.weights = std::span(weights, weight_count);
  job.normal_mode = static_cast<facerig::NormalMode>(mode);
  job.out_positions = std::span(reinterpret_cast<glm::vec3*>(positions), r.vertex_count());
  if (mode != FR_NORMALS_NONE) job.out_normals = std::span(reinterpret_cast<glm::vec3*>(normals), r.vertex_count());
  job.state = state;
  const facerig::BlendJobError error = job.Run();
  if (error == facerig::BlendJobError::kNone) return FR_OK;
  return Fail(FR_ERROR_INVALID_ARGUMENT, {"blend: ", facerig::ToString(error)});
}

}  // namespace

extern "C" {

fr_status fr_rig_blend(const fr_rig* rig, const float* weights, size_t weight_count, fr_normal_mode mode,
                       float* positions, float* normals, size_t vertex_capacity) {
  return Guard([&] {
    FR_REQUIRE(rig, "rig");
    return Blend(rig->data->rig, nullptr, weights, weight_count, mode, positions, normals, vertex_capacity);
  });
}

fr_status fr_blender_create(fr_rig* rig, fr_blender** out_blender) {
  return Guard([&] {
    FR_REQUIRE(out_blender, "out_blender");
    *out_blender = nullptr;
    FR_REQUIRE(rig, "rig");
    *out_blender = std::make_unique<fr_blender>(rig->data).release();
    return FR_OK;
  });
}

void fr_blender_release(fr_blender* blender) { delete blender; }

fr_status fr_blender_blend(fr_blender* blender, const float* weights, size_t weight_count, fr_normal_mode mode,
                           float* positions, float* normals, size_t vertex_capacity) {
  return Guard([&] {
    FR_REQUIRE(blender, "blender");
    return Blend(blender->rig->rig, &blender->state, weights, weight_count, mode, positions, normals,
                 vertex_capacity);
  });
}

fr_status fr_blender_reset(fr_blender* blender) {
  FR_REQUIRE(blender, "blender");
  blender->state.Reset();
  return FR_OK;
}

}  // extern "C"
