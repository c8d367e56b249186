// The landmarks a face's stages pass on (detected, read from a file, or the
// template's own vertices), apart from the detector that finds them
// (landmarks.h): headers that only carry landmarks (rig_build.h,
// face_template.h) include this one.
#pragma once

#include <bitset>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace facerig {

// Which of the 68 landmarks (bit k: dlib point k).
using LandmarkMask = std::bitset<68>;

// The landmarks in `mask`, in order.
inline std::vector<std::uint32_t> IndicesOf(const LandmarkMask& mask) {
  std::vector<std::uint32_t> indices;
  for (std::uint32_t k = 0; k < mask.size(); ++k) {
    if (mask[k]) indices.push_back(k);
  }
  return indices;
}

// 3D landmarks with a confidence in [0, 1] each. `indices` names each point's
// dlib landmark (0..67): a detected set has all 68 in order; a manual file may
// hold only a handful.
struct FaceLandmarks {
  std::vector<glm::vec3> points;
  std::vector<float> confidence;
  std::vector<std::uint32_t> indices;
};

// Lid landmarks the detector found off the skin with no opening margin to go
// to: on the eyeball or the tear film, where the lid is or 3-6 mm off it. The
// detector leaves them out of its landmarks (confidence 0) and keeps them
// here; neither trusting nor dropping them holds on every face, so
// BuildRigChoosingLids (rigging/lid_choice.h) builds both ways.
struct DoubtfulLidPoints {
  LandmarkMask points;
  std::vector<float> confidence;  // per landmark, as detected; 0 where not doubtful
};

}  // namespace facerig
