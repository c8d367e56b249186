// The per-vertex attribute a_mouth_light of the face program (face_shaders.cpp).
#pragma once

#include <vector>

#include <glm/mat4x4.hpp>

#include "facerig/runtime/rig.h"

namespace facerig::player {

// How much light reaches each vertex inside the mouth: 1 outside it and at
// the front of the teeth, falling towards the back of the mouth, so that an
// open mouth shows a dark cavity instead of a fully lit tongue (the lights
// have no shadows). Teeth, gums, tongue and mouth-interior parts, by depth
// behind the mouth parts' front along the scene's forward axis (+Z), over
// their width. `rig_to_scene` maps rig units to the scene.
std::vector<float> MouthLight(const Rig& rig, const glm::mat4& rig_to_scene);

}  // namespace facerig::player
