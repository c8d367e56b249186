// The face's outline in a photograph by dlib's 68 points: the jaw line, then
// the brows lifted up towards the forehead. The skin masks of the texture and
// of the shading fit and the hair's seeds all start from it.
#pragma once

#include <span>
#include <vector>

#include <glm/vec2.hpp>

namespace facerig {

// The jaw line (points 0-16), then the brows from the left brow's outer end
// back to the right brow's (26 down to 17), each moved by forehead times the
// chin-to-brows vector (0: the brows themselves; 0.35 about reaches the hairline).
std::vector<glm::vec2> FaceOutline(std::span<const glm::vec2> landmarks, float forehead);

}  // namespace facerig
