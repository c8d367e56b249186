// The per-vertex attribute a_radial of the face program (face_shaders.cpp).
#pragma once

#include <vector>

#include <glm/mat4x4.hpp>

#include "facerig/runtime/rig.h"

namespace facerig::player {

// The iris shading reads a_radial: 0 at the iris centre, 1 at its rim
// (-1: not an eye vertex). For rigs without a pupil mesh (ICT-FaceKit),
// whose opaque sclera covers the iris mesh, the sclera itself carries the
// iris. It is attached to the vertices, so it follows eyeLook* shapes.
// `rig_to_scene` gives the forward axis (+Z in the scene) in rig units.
std::vector<float> IrisRadial(const Rig& rig, const glm::mat4& rig_to_scene, bool procedural_pupil);

}  // namespace facerig::player
