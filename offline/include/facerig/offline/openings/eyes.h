// The eyes as openings of a face mesh: boundary loops, and the eye landmarks
// put onto the lid margins where an eye is a hole in the mesh.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/offline/landmarks/face_landmarks.h"
#include "facerig/runtime/mesh.h"

namespace facerig {

// Boundary loops of the mesh (holes: eye openings, an open mouth, the neck),
// as vertex chains of at least 6 vertices. Non-manifold corners end a chain early.
std::vector<std::vector<std::uint32_t>> BoundaryLoops(std::span<const glm::vec3> positions,
                                                     std::span<const Triangle> triangles);

// Where an eye is a hole in the face mesh (a separate eyeball behind it: most
// game and scanned heads), the hole's boundary is the lid margins, a better
// guide than a 2D detector trained on photographs, which misplaces a stylized
// head's eyes.
//
// Where an eye is an opening in the mesh, its corners (dlib 36/39, 42/45) are
// the ends of the opening's first principal axis. Moves only corners within
// 0.3 eye widths. Returns how many moved.
int CorrectEyeCorners(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                      std::vector<glm::vec3>& points);

struct EyeOpeningFit {
  int eyes = 0;  // eyes fitted to an opening
  LandmarkMask moved;  // points put on a margin
};

// Each eye (dlib 36-41, 42-47) onto the opening near them: the corners go to
// the ends of its principal axis; a lid point goes onto its upper or lower
// chain, at its place along that axis, when the detector missed the eye (its
// lid points far from the margins) or when `inside` marks it (it landed on
// the eyeball or tear film seen through the opening). Other lid points stay:
// a template's lid landmarks need not lie on its margin. An eye is fitted to
// the largest opening whose centre lies within 0.75 of the detected eye width
// of the detected eye's centre and whose size is 0.2 to 0.8 of that width
// (an iris may be a hole too), unless a point would move farther than 0.75
// of the width (the opening is then not this eye). points: the 68 landmarks.
EyeOpeningFit FitEyesToOpenings(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                                std::vector<glm::vec3>& points, const LandmarkMask& inside = {});

}  // namespace facerig
