// The landmarks a face's stages pass on (detected, read from a file, or the
// template's own vertices), apart from the detector that finds them
// (landmarks.h): headers that only carry landmarks (rig_build.h,
// face_template.h) include this one.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace facerig {

// 3D landmarks with a confidence in [0, 1] each. `indices` names each point's
// dlib landmark (0..67): a detected set has all 68 in order; a manual file may
// hold only a handful.
struct FaceLandmarks {
  std::vector<glm::vec3> points;
  std::vector<float> confidence;
  std::vector<std::uint32_t> indices;
};

}  // namespace facerig
