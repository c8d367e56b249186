#include "iris_radial.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "face_renderer.h"
#include "part_vertices.h"

namespace facerig::player {
namespace {

// A sclera that carries the iris: the angle from the eyeball's forward axis
// over the iris's angular radius.
void SetScleraRadial(std::span<const glm::vec3> positions, const std::vector<std::uint32_t>& vertices,
                     const glm::vec3& center, const glm::vec3& forward, std::vector<float>* radial) {
  constexpr float kIrisHalfAngle = 0.52f;  // a 12 mm iris on a 24 mm eyeball
  for (std::uint32_t v : vertices) {
    const glm::vec3 d = positions[v] - center;
    const float length = glm::length(d);
    const float angle = length > 0.0f ? std::acos(std::clamp(glm::dot(d / length, forward), -1.0f, 1.0f)) : 3.0f;
    (*radial)[v] = angle / kIrisHalfAngle;
  }
}

// An iris mesh: distance across the forward axis over the part's radius
// (a domed iris works too).
void SetIrisRadial(std::span<const glm::vec3> positions, const std::vector<std::uint32_t>& vertices,
                   const glm::vec3& center, const glm::vec3& forward, std::vector<float>* radial) {
  float max_distance = 0.0f;
  for (std::uint32_t v : vertices) {
    const glm::vec3 d = positions[v] - center;
    max_distance = std::max(max_distance, glm::length(d - forward * glm::dot(d, forward)));
  }
  for (std::uint32_t v : vertices) {
    const glm::vec3 d = positions[v] - center;
    (*radial)[v] = max_distance > 0.0f ? glm::length(d - forward * glm::dot(d, forward)) / max_distance : 0.0f;
  }
}

}  // namespace

std::vector<float> IrisRadial(const Rig& rig, const glm::mat4& rig_to_scene, bool procedural_pupil) {
  std::vector<float> radial(rig.vertex_count(), -1.0f);
  const std::span<const glm::vec3> positions = rig.positions();
  const glm::vec3 forward = glm::normalize(glm::vec3(glm::inverse(rig_to_scene) * glm::vec4(0, 0, 1, 0)));
  for (const Part& part : rig.parts()) {
    const Material material = MaterialForPart(part.name);
    if (material != Material::kIris && !(material == Material::kSclera && procedural_pupil)) continue;
    const std::vector<std::uint32_t> vertices = VerticesOfParts(rig, [&](const Part& p) { return &p == &part; });
    if (vertices.empty()) continue;
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (std::uint32_t v : vertices) {
      lo = glm::min(lo, positions[v]);
      hi = glm::max(hi, positions[v]);
    }
    const glm::vec3 center = (lo + hi) * 0.5f;
    if (material == Material::kSclera) {
      SetScleraRadial(positions, vertices, center, forward, &radial);
    } else {
      SetIrisRadial(positions, vertices, center, forward, &radial);
    }
  }
  return radial;
}

}  // namespace facerig::player
