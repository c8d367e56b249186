// Per-frame blending into the caller's buffers (BlendJob): no allocation.
#include <span>

#include <glm/vec3.hpp>

#include "boundary.h"
#include "facerig/runtime/blend_job.h"
#include "handles.h"

static_assert(sizeof(glm::vec3) == 3 * sizeof(float) && alignof(glm::vec3) == alignof(float),
              "caller float triples are read as glm::vec3");

using namespace facerig::capi;

extern "C" {

fr_status fr_rig_blend(const fr_rig* rig, const float* weights, size_t weight_count, fr_normal_mode mode,
                       float* positions, float* normals, size_t vertex_capacity) {
  return Guard([&] {
    FR_REQUIRE(rig, "rig");
    if (weights == nullptr && weight_count > 0) return Fail(FR_ERROR_INVALID_ARGUMENT, "weights is NULL");
    FR_REQUIRE(positions, "positions");
    const facerig::Rig& r = rig->data->rig;
    if (weight_count != r.shape_count()) {
      char given[24], count[24];
      return Fail(FR_ERROR_INVALID_ARGUMENT, {"weight_count is ", Number(weight_count, given),
                                              ", the rig has ", Number(r.shape_count(), count), " shapes"});
    }
    if (mode != FR_NORMALS_NONE && mode != FR_NORMALS_BLEND_DELTAS && mode != FR_NORMALS_RECOMPUTE) {
      return Fail(FR_ERROR_INVALID_ARGUMENT, "mode is not an fr_normal_mode");
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
    const facerig::BlendJobError error = job.Run();
    if (error == facerig::BlendJobError::kNone) return FR_OK;
    return Fail(FR_ERROR_INVALID_ARGUMENT, {"blend: ", facerig::ToString(error)});
  });
}

}  // extern "C"
