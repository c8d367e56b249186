// A material's base colour for the face program (MaterialForPart and
// ToString are declared in face_renderer.h).
#pragma once

#include <glm/vec3.hpp>

#include "face_renderer.h"

namespace facerig::player {

// Linear RGB (the face shader outputs gamma 2.2); black for kHidden.
glm::vec3 BaseColor(Material material);

}  // namespace facerig::player
