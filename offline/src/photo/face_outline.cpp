#include "photo/face_outline.h"

#include "facerig/offline/landmarks/dlib68.h"

namespace facerig {

std::vector<glm::vec2> FaceOutline(std::span<const glm::vec2> landmarks, float forehead) {
  const glm::vec2 brows = 0.5f * (landmarks[dlib68::kRightBrowPeak] + landmarks[dlib68::kLeftBrowPeak]);
  const glm::vec2 lift = forehead * (brows - landmarks[dlib68::kChin]);
  std::vector<glm::vec2> outline(landmarks.begin() + dlib68::kJawFirst, landmarks.begin() + dlib68::kJawLast + 1);
  for (std::size_t k = dlib68::kLeftBrowLast + 1; k-- > dlib68::kRightBrowFirst;) outline.push_back(landmarks[k] + lift);
  return outline;
}

}  // namespace facerig
