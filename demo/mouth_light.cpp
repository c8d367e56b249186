#include "mouth_light.h"

#include <algorithm>
#include <cstdint>
#include <limits>

#include "face_materials.h"
#include "part_vertices.h"

namespace facerig::player {
namespace {

bool InsideMouth(Material material) {
  return material == Material::kTeeth || material == Material::kGums || material == Material::kTongue ||
         material == Material::kMouthInner;
}

}  // namespace

std::vector<float> MouthLight(const Rig& rig, const glm::mat4& rig_to_scene) {
  std::vector<float> light(rig.vertex_count(), 1.0f);
  const std::vector<std::uint32_t> vertices =
      VerticesOfParts(rig, [](const Part& part) { return InsideMouth(MaterialForPart(part.name)); });
  if (vertices.empty()) return light;
  float front = -std::numeric_limits<float>::max();
  float left = std::numeric_limits<float>::max(), right = -std::numeric_limits<float>::max();
  std::vector<glm::vec3> scene(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    scene[i] = glm::vec3(rig_to_scene * glm::vec4(rig.positions()[vertices[i]], 1.0f));
    front = std::max(front, scene[i].z);
    left = std::min(left, scene[i].x);
    right = std::max(right, scene[i].x);
  }
  // A third of the mouth's width behind its front, a vertex is in the dark.
  const float reach = 0.33f * (right - left);
  if (!(reach > 0.0f)) return light;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const float lit = std::clamp(1.0f - (front - scene[i].z) / reach, 0.0f, 1.0f);
    light[vertices[i]] = 0.06f + 0.94f * lit * lit;
  }
  return light;
}

}  // namespace facerig::player
