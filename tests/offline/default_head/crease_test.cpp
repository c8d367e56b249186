// The built-in head's cheeks stay smooth in speech: no fold along the control
// face's edges from the nose wing past the mouth corner to the jaw.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/default_head/default_head.h"
#include "support/default_head_poses.h"

namespace {

struct Fold {
  double left = 0.0, right = 0.0;  // degrees, the character's left (+X) and right
};

// The largest increase over rest of the angle between the normals of two
// adjacent skin triangles, on the front of the lower face around the mouth
// (from the nose wing to the jaw), the lips themselves left out.
Fold CheekFold(const facerig::Rig& rig, const facerig::DefaultHeadFeatures& features,
               const std::vector<glm::vec3>& pose) {
  const auto rest = rig.positions();
  const facerig::Part* skin = rig.FindPart("skin");
  REQUIRE(skin);
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> edge_triangles;
  for (std::uint32_t t = skin->first_triangle; t < skin->first_triangle + skin->triangle_count; ++t) {
    const facerig::Triangle& tri = rig.triangles()[t];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
      edge_triangles[{std::min(a, b), std::max(a, b)}].push_back(t);
    }
  }
  auto normal = [&](std::uint32_t t, const auto& positions) {
    const facerig::Triangle& tri = rig.triangles()[t];
    const glm::dvec3 a = positions[tri[0]], b = positions[tri[1]], c = positions[tri[2]];
    return glm::normalize(glm::cross(b - a, c - a));
  };
  auto dihedral = [&](const std::vector<std::uint32_t>& t, const auto& positions) {
    const double cosine = std::clamp(glm::dot(normal(t[0], positions), normal(t[1], positions)), -1.0, 1.0);
    return std::acos(cosine) * 180.0 / 3.14159265358979;
  };
  auto near_lip_margin = [&](const glm::vec3& p) {
    for (const auto* chain : {&features.upper_lip, &features.lower_lip}) {
      for (std::uint32_t v : *chain) {
        if (glm::length(rest[v] - p) < 0.5f) return true;
      }
    }
    return false;
  };
  Fold fold;
  for (const auto& [edge, triangles] : edge_triangles) {
    if (triangles.size() != 2) continue;
    const glm::vec3 m = 0.5f * (rest[edge.first] + rest[edge.second]);
    const float x = std::abs(m.x);
    if (m.z < 3.0f || m.y > -2.5f || m.y < -11.0f || x < 1.0f || x > 6.0f) continue;
    const bool lips = x < 2.7f && m.y > -7.7f && m.y < -5.1f;
    if (lips || near_lip_margin(m)) continue;
    const double increase = dihedral(triangles, pose) - dihedral(triangles, rest);
    double& side = m.x > 0.0f ? fold.left : fold.right;
    side = std::max(side, increase);
  }
  return fold;
}

}  // namespace

TEST_CASE("Default head: speech leaves no crease on the cheeks, the same on both sides", "[default_head]") {
  facerig::DefaultHeadFeatures features;
  const facerig::Rig& rig = facerig::test::DefaultHead(&features);
  // "oh" as the player speaks it, and the shapes of speech one at a time.
  const std::vector<std::vector<std::pair<std::string, float>>> poses = {
      {{"jawOpen", 0.4f}, {"mouthFunnel", 0.6f}, {"mouthPucker", 0.1f}},
      {{"mouthFunnel", 1.0f}},
      {{"mouthPucker", 1.0f}},
      {{"jawOpen", 0.4f}},
      {{"mouthLowerDown_L", 1.0f}, {"mouthLowerDown_R", 1.0f}},
  };
  for (const auto& pose : poses) {
    INFO(pose.front().first << " " << pose.front().second << " (" << pose.size() << " shapes)");
    const Fold fold = CheekFold(rig, features, facerig::test::Posed(rig, pose));
    INFO("fold left " << fold.left << " right " << fold.right << " degrees");
    CHECK(fold.left < 12.0);
    // The control face is mirrored exactly, and so is every unsided shape.
    CHECK(fold.right == Approx(fold.left).margin(0.01));
  }
}
