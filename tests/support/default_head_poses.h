// The built-in head for the tests: built once per process (a few seconds;
// the [default_head] tests run in one process, tests/CMakeLists.txt), and
// posed by shape weights.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/vec3.hpp>

#include "facerig/offline/default_head/default_head.h"
#include "facerig/runtime/blend_job.h"

namespace facerig::test {

inline const Rig& DefaultHead(DefaultHeadFeatures* features_out = nullptr) {
  static DefaultHeadFeatures features;
  static const Rig rig = BuildDefaultHead(&features);
  if (features_out) *features_out = features;
  return rig;
}

// The rig's positions at these weights (every other shape at 0).
inline std::vector<glm::vec3> Posed(const Rig& rig, const std::vector<std::pair<std::string, float>>& weights) {
  std::vector<float> w(rig.shape_count(), 0.0f);
  for (const auto& [name, value] : weights) {
    const auto index = rig.FindShape(name);
    REQUIRE(index);
    w[*index] = value;
  }
  std::vector<glm::vec3> positions(rig.vertex_count());
  BlendJob job{&rig, w, NormalMode::kNone, positions, {}};
  REQUIRE(job.Run() == BlendJobError::kNone);
  return positions;
}

}  // namespace facerig::test
