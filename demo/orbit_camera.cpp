#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "face_renderer.h"

namespace facerig::player {

void OrbitCamera::Orbit(float dx_degrees, float dy_degrees) {
  yaw_degrees += dx_degrees;
  pitch_degrees = std::clamp(pitch_degrees + dy_degrees, -80.0f, 80.0f);
}

void OrbitCamera::Zoom(float steps) { distance *= std::pow(0.9f, steps); }

glm::mat4 OrbitCamera::View() const {
  const float yaw = glm::radians(yaw_degrees), pitch = glm::radians(pitch_degrees);
  const glm::vec3 direction(std::sin(yaw) * std::cos(pitch), std::sin(pitch),
                            std::cos(yaw) * std::cos(pitch));
  return glm::lookAt(target + direction * distance, target, glm::vec3(0, 1, 0));
}

glm::mat4 OrbitCamera::Projection(float aspect) const {
  return glm::perspective(glm::radians(fov_degrees), aspect, distance * 0.05f, distance * 20.0f);
}

}  // namespace facerig::player
