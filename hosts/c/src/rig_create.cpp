// Rigs from the caller's arrays: a mesh and dense shape deltas held by another
// program (a Blender object and its shape keys), validated as a loaded rig is.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "boundary.h"
#include "facerig/runtime/rig_builder.h"
#include "handles.h"

namespace facerig::capi {
namespace {

// Deltas shorter than this fraction of the mesh's bounding diagonal are left
// out of the sparse shapes: far below what a frame shows.
constexpr float kDropFraction = 1e-7f;

float BoundingDiagonal(const std::vector<glm::vec3>& positions) {
  glm::vec3 low = positions.front(), high = positions.front();
  for (const glm::vec3& p : positions) {
    low = glm::min(low, p);
    high = glm::max(high, p);
  }
  return glm::length(high - low);
}

fr_status CheckFinite(const float* values, std::size_t count, const char* what) {
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(values[i])) {
      char at[24];
      return Fail(FR_ERROR_INVALID_ARGUMENT, {what, " value ", Number(i, at), " is NaN or infinite"});
    }
  }
  return FR_OK;
}

}  // namespace
}  // namespace facerig::capi

using namespace facerig::capi;

extern "C" {

fr_status fr_rig_create(const float* positions, size_t vertex_count, const uint32_t* triangles,
                        size_t triangle_count, const char* const* shape_names, const float* deltas,
                        size_t shape_count, fr_rig** out_rig) {
  return Guard([&] {
    FR_REQUIRE(out_rig, "out_rig");
    *out_rig = nullptr;
    FR_REQUIRE(positions, "positions");
    FR_REQUIRE(triangles, "triangles");
    if (shape_count > 0) {
      FR_REQUIRE(shape_names, "shape_names");
      FR_REQUIRE(deltas, "deltas");
    }
    if (vertex_count == 0 || vertex_count > 0xFFFFFFF0u) {
      return Fail(FR_ERROR_INVALID_ARGUMENT, "vertex_count must lie in [1, 4294967280]");
    }
    if (shape_count > SIZE_MAX / 3 / vertex_count) return Fail(FR_ERROR_INVALID_ARGUMENT, "shape_count is absurd");
    if (const fr_status s = CheckFinite(positions, 3 * vertex_count, "position"); s != FR_OK) return s;
    if (const fr_status s = CheckFinite(deltas, 3 * vertex_count * shape_count, "delta"); s != FR_OK) return s;
    facerig::RawRig raw;
    raw.positions.resize(vertex_count);
    std::memcpy(raw.positions.data(), positions, sizeof(float) * 3 * vertex_count);
    raw.triangles.resize(triangle_count);
    for (std::size_t t = 0; t < triangle_count; ++t) {
      raw.triangles[t] = {triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]};
    }
    const float drop = kDropFraction * BoundingDiagonal(raw.positions);
    raw.shapes.reserve(shape_count);
    for (std::size_t s = 0; s < shape_count; ++s) {
      if (shape_names[s] == nullptr) {
        char at[24];
        return Fail(FR_ERROR_INVALID_ARGUMENT, {"shape_names[", Number(s, at), "] is NULL"});
      }
      const auto* dense = reinterpret_cast<const glm::vec3*>(deltas + 3 * vertex_count * s);
      raw.shapes.push_back(facerig::MakeSparseShape(shape_names[s], std::span(dense, vertex_count), {}, drop));
    }
    std::string problem;
    std::optional<facerig::Rig> rig = facerig::RigBuilder::Build(std::move(raw), &problem);
    if (!rig) return Fail(FR_ERROR_INVALID_ARGUMENT, {"the arrays do not make a rig: ", problem});
    auto handle = std::make_unique<fr_rig>();
    handle->data = std::make_shared<const LoadedRig>(std::move(*rig));
    *out_rig = handle.release();
    return FR_OK;
  });
}

}  // extern "C"
