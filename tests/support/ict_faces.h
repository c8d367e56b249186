// The tests' shortcuts to the registration targets (measure/registration_targets.h):
// ICT-FaceKit read from the tests' IctDir() (../shared/data), once per process.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "measure/registration_targets.h"
#include "support/test_meshes.h"

namespace facerig::test {

inline const IctFaceModel& IctFaces() {
  static const IctFaceModel model = LoadIctFaces(IctDir());
  return model;
}
// ICT-FaceKit's template description (landmark vertices, parts), once per process.
inline const FaceTemplateInfo& IctTemplateInfo() {
  static const FaceTemplateInfo info = LoadIctTemplateInfo(IctRig());
  return info;
}
inline std::vector<glm::vec3> RandomIctFace(std::uint32_t seed, double sigma = 1.0) {
  return RandomIctFace(IctFaces(), seed, sigma);
}
inline RegistrationTarget MakeRegistrationTarget(const RegistrationTargetOptions& options) {
  return MakeRegistrationTarget(IctFaces(), options);
}

}  // namespace facerig::test
