// BlendJob::Run with a BlendState: writes only what moved (blend_plan.h).
#pragma once

#include <span>

#include <glm/vec3.hpp>

#include "facerig/runtime/blend_job.h"

namespace facerig {

class BlendPlan;

class SparseBlend {
 public:
  // `job` is valid (Validate) and has a state.
  static void Run(const BlendJob& job);

 private:
  explicit SparseBlend(const BlendJob& job);
  void CollectActiveSets();
  void Positions();
  void RestoreNormals(std::span<const glm::vec3> rest, std::span<const glm::vec3> base);
  void BlendedNormals();
  void BlendedRecomputedNormals();
  void Remember();

  const BlendJob& job_;
  BlendState& state_;
  const BlendPlan& plan_;
  glm::vec3* positions_;
  glm::vec3* normals_;  // null for kNone
  bool normals_known_;  // the normals buffer holds the last Run's, in this mode
};

}  // namespace facerig
