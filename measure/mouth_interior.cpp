#include "measure/mouth_interior.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include <glm/geometric.hpp>

#include "facerig/offline/error.h"

namespace facerig {
namespace {

float MedianMotion(std::span<const glm::vec3> neutral, std::span<const glm::vec3> moved,
                   const std::vector<std::uint32_t>& vertices) {
  std::vector<float> motion;
  for (std::uint32_t v : vertices) motion.push_back(glm::length(moved[v] - neutral[v]));
  if (motion.empty()) return 0.0f;
  std::nth_element(motion.begin(), motion.begin() + static_cast<std::ptrdiff_t>(motion.size() / 2), motion.end());
  return motion[motion.size() / 2];
}

// The head's mouth in its rest pose: the seam's height (its corners'), its
// middle and half width across.
struct MouthFrame {
  float seam_y = 0.0f, centre_x = 0.0f, half_width = 0.0f;

  MouthFrame(std::span<const glm::vec3> neutral, std::array<std::uint32_t, 2> corners) {
    const glm::vec3 a = neutral[corners[0]], b = neutral[corners[1]];
    seam_y = 0.5f * (a.y + b.y);
    centre_x = 0.5f * (a.x + b.x);
    half_width = 0.5f * std::abs(a.x - b.x);
  }
  bool Between(glm::vec3 p) const { return std::abs(p.x - centre_x) <= half_width; }
};

std::vector<std::uint8_t> VerticesOfPart(const Rig& rig, std::string_view name) {
  std::vector<std::uint8_t> in(rig.vertex_count(), 0);
  for (const Part& part : rig.parts()) {
    if (part.name != name) continue;
    for (std::uint32_t t = part.first_triangle; t < part.first_triangle + part.triangle_count; ++t) {
      for (std::uint32_t v : rig.triangles()[t]) in[v] = 1;
    }
  }
  return in;
}

glm::vec3 FaceNormal(std::span<const glm::vec3> p, const Triangle& t) {
  const glm::vec3 n = glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
  const float length = glm::length(n);
  return length > 0.0f ? n / length : glm::vec3(0.0f);
}

// The signed angle (radians) between two triangles' normals about their shared edge.
float Bend(std::span<const glm::vec3> p, const Triangle& a, const Triangle& b, std::uint32_t u, std::uint32_t w) {
  const glm::vec3 na = FaceNormal(p, a), nb = FaceNormal(p, b);
  const glm::vec3 edge = glm::normalize(p[w] - p[u]);
  return std::atan2(glm::dot(glm::cross(na, nb), edge), glm::dot(na, nb));
}

}  // namespace

std::vector<glm::vec3> PoseWithShape(const Rig& rig, std::string_view name) {
  const std::optional<std::size_t> found = rig.FindShape(name);
  if (!found) throw InvalidInputError("mouth measure: the rig has no shape " + std::string(name));
  std::vector<glm::vec3> positions(rig.positions().begin(), rig.positions().end());
  const BlendShapeView shape = rig.shape(*found);
  for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
    positions[shape.vertex_indices[i]] += shape.position_deltas[i];
  }
  return positions;
}

MouthCurtain MeasureMouthCurtain(const Rig& head, const Rig& built, const DefaultHeadFeatures& features) {
  if (head.vertex_count() != built.vertex_count()) {
    throw InvalidInputError("mouth measure: the built rig has " + std::to_string(built.vertex_count()) +
                            " vertices, the head " + std::to_string(head.vertex_count()));
  }
  const std::span<const glm::vec3> neutral = head.positions();
  const std::vector<glm::vec3> own_open = PoseWithShape(head, "jawOpen");
  const std::vector<glm::vec3> built_open = PoseWithShape(built, "jawOpen");
  const float own_lower_lip = MedianMotion(neutral, own_open, features.lower_lip);
  MouthCurtain curtain;
  curtain.lower_lip_motion = MedianMotion(neutral, built_open, features.lower_lip);
  const MouthFrame mouth(neutral, features.mouth_corners);
  const std::vector<std::uint8_t> in_sack = VerticesOfPart(head, "mouth_inner");
  for (std::uint32_t v = 0; v < neutral.size(); ++v) {
    const glm::vec3 p = neutral[v];
    const bool skin = v < features.skin_vertex_count;
    if (!(skin || in_sack[v]) || p.y < mouth.seam_y || !mouth.Between(p)) continue;
    if (!(glm::length(own_open[v] - p) < 0.1f * own_lower_lip)) continue;
    ++curtain.upper_vertices;
    const float ratio = glm::length(built_open[v] - p) / curtain.lower_lip_motion;
    curtain.worst_ratio = std::max(curtain.worst_ratio, ratio);
    if (!(ratio > 0.5f)) continue;
    ++(skin ? curtain.skin_on_jaw : curtain.sack_on_jaw);
  }
  return curtain;
}

LipFold MeasureLipFold(const Rig& rig, const DefaultHeadFeatures& features) {
  return MeasureLipFold(rig, features.mouth_corners, features.lower_lip_border, features.skin_vertex_count);
}

LipFold MeasureLipFold(const Rig& rig, std::array<std::uint32_t, 2> mouth_corners, std::uint32_t lower_lip_bottom,
                       std::uint32_t skin_vertex_count) {
  if (mouth_corners[0] >= rig.vertex_count() || mouth_corners[1] >= rig.vertex_count() ||
      lower_lip_bottom >= rig.vertex_count()) {
    throw InvalidInputError("mouth measure: mouth corner vertex out of range (" + std::to_string(rig.vertex_count()) +
                            " vertices)");
  }
  const std::span<const glm::vec3> neutral = rig.positions();
  const float lip_bottom = neutral[lower_lip_bottom].y;
  const std::vector<glm::vec3> open = PoseWithShape(rig, "jawOpen");
  const MouthFrame mouth(neutral, mouth_corners);
  std::vector<glm::vec3> normals(neutral.size(), glm::vec3(0.0f));
  const std::span<const Triangle> triangles = rig.triangles();
  for (const Triangle& t : triangles) {
    for (std::uint32_t v : t) normals[v] += FaceNormal(neutral, t);
  }
  auto in_region = [&](std::uint32_t v) {
    const glm::vec3 p = neutral[v];
    const float below = lip_bottom - p.y;
    return v < skin_vertex_count && mouth.Between(p) && below > 0.0f && below <= mouth.half_width &&
           glm::normalize(normals[v]).z >= 0.5f;
  };
  // Each edge of the region's triangles with the triangles on either side.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::size_t>> sides;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Triangle& tri = triangles[t];
    if (!in_region(tri[0]) || !in_region(tri[1]) || !in_region(tri[2])) continue;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
      sides[{std::min(a, b), std::max(a, b)}].push_back(t);
    }
  }
  LipFold fold;
  for (const auto& [edge, on] : sides) {
    if (on.size() != 2) continue;
    ++fold.edges;
    const Triangle& a = triangles[on[0]];
    const Triangle& b = triangles[on[1]];
    float change = Bend(open, a, b, edge.first, edge.second) - Bend(neutral, a, b, edge.first, edge.second);
    change = std::abs(std::remainder(change, 2.0f * 3.14159265f));
    const float degrees = change * 180.0f / 3.14159265f;
    if (degrees <= fold.degrees) continue;
    fold.degrees = degrees;
    fold.at = 0.5f * (neutral[edge.first] + neutral[edge.second]);
    fold.below_lip = lip_bottom - fold.at.y;
  }
  return fold;
}

}  // namespace facerig
