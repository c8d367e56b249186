// The built-in head deformed onto a photo's landmarks: its lid rims go onto
// the photo's lids (FitLidMarginsToPhoto), the eyeballs follow, the rest of
// the face stays.
#include <catch2/catch.hpp>

#include <cmath>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "facerig/offline/default_head/default_head.h"
#include "facerig/offline/photo/fit.h"
#include "facerig/runtime/rig_builder.h"
#include "photo/fit/eye_fit.h"
#include "support/default_head_poses.h"

namespace facerig {
namespace {

constexpr int kImageSize = 512;

// Looking at the face square on, the head's bounding diagonal 300 px, the
// landmarks' middle in the middle of the image.
ScaledOrthoCamera FrontCamera(const Rig& head, const std::vector<std::uint32_t>& landmark_vertices) {
  glm::vec3 middle(0.0f);
  for (const std::uint32_t v : landmark_vertices) middle += head.positions()[v] / static_cast<float>(landmark_vertices.size());
  ScaledOrthoCamera camera;
  camera.scale = 300.0f / head.bounding_diagonal();
  camera.translation = -camera.scale * glm::vec2(middle.x, middle.y);
  return camera;
}

glm::vec2 Project(const ScaledOrthoCamera& camera, const glm::vec3& p) { return ProjectPixel(camera, p, kImageSize, kImageSize); }

float MeanY(const ScaledOrthoCamera& camera, const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& margin) {
  // The middle half of the margin: the corners stay where they were.
  float sum = 0.0f;
  int count = 0;
  for (std::size_t i = margin.size() / 4; i < margin.size() - margin.size() / 4; ++i, ++count) {
    sum += Project(camera, positions[margin[i]]).y;
  }
  return sum / static_cast<float>(count);
}

// Stand-ins for dlib's 68 landmark vertices: the eyes' points (36-47) on the
// lid margins (their ends and thirds; 36-41 the image's left eye, the
// character's right), the others on the nose tip, the mouth corners and
// cheeks (repeats are one point to the deformation).
std::vector<std::uint32_t> LandmarkVertices(const DefaultHeadFeatures& features) {
  std::vector<std::uint32_t> vertices(68, features.nose_tip);
  for (std::size_t k = 0; k < 17; ++k) vertices[k] = features.cheeks[k % 2];
  for (std::size_t k = 48; k < 68; ++k) vertices[k] = features.mouth_corners[k % 2];
  for (const auto& [first, eye] : {std::pair{std::size_t{36}, 1}, std::pair{std::size_t{42}, 0}}) {
    const std::vector<std::uint32_t>& upper = features.upper_lid[static_cast<std::size_t>(eye)];
    const std::vector<std::uint32_t>& lower = features.lower_lid[static_cast<std::size_t>(eye)];
    const auto at = [](const std::vector<std::uint32_t>& margin, float t) {
      return margin[static_cast<std::size_t>(std::lround(t * static_cast<float>(margin.size() - 1)))];
    };
    vertices[first] = upper.front(), vertices[first + 3] = upper.back();
    vertices[first + 1] = at(upper, 1.0f / 3.0f), vertices[first + 2] = at(upper, 2.0f / 3.0f);
    vertices[first + 5] = at(lower, 1.0f / 3.0f), vertices[first + 4] = at(lower, 2.0f / 3.0f);
  }
  return vertices;
}

// The built-in head seen from the front, with its landmark vertices' projections.
struct FrontHead {
  DefaultHeadFeatures features;
  const Rig& head = test::DefaultHead(&features);
  const Mesh surface = NeutralMesh(head);
  const std::vector<std::uint32_t> landmark_vertices = LandmarkVertices(features);
  const ScaledOrthoCamera camera = FrontCamera(head, landmark_vertices);
  std::vector<glm::vec3> posed{head.positions().begin(), head.positions().end()};
  std::vector<glm::vec3> rest = posed;
};

}  // namespace

TEST_CASE("photo rig: the built-in head's lid rims move onto a photo's lids, the eyeballs with them", "[photo_rig]") {
  FrontHead front;
  auto& [features, head, surface, landmark_vertices, camera, posed, rest] = front;
  // The photo's lids: its upper lid points 3 px higher than the head's, its
  // lower lid points 2 px lower (a wider opening), the corners where they are.
  std::vector<glm::vec2> landmarks;
  for (const std::uint32_t v : landmark_vertices) landmarks.push_back(Project(camera, posed[v]));
  for (const int k : {37, 38, 43, 44}) landmarks[static_cast<std::size_t>(k)].y -= 3.0f;
  for (const int k : {40, 41, 46, 47}) landmarks[static_cast<std::size_t>(k)].y += 2.0f;
  const std::vector<glm::vec3> before = posed;

  const LidMarginFit fit =
      FitLidMarginsToPhoto(surface, landmarks, landmark_vertices, camera, kImageSize, kImageSize, posed, rest);
  CHECK(fit.eyes == 2);
  CHECK(fit.margins >= features.upper_lid[0].size() + features.lower_lid[0].size());
  for (int eye = 0; eye < 2; ++eye) {
    INFO("eye " << eye);
    const float upper = MeanY(camera, posed, features.upper_lid[eye]) - MeanY(camera, before, features.upper_lid[eye]);
    const float lower = MeanY(camera, posed, features.lower_lid[eye]) - MeanY(camera, before, features.lower_lid[eye]);
    CHECK(upper == Approx(-3.0f).margin(1.0f));
    CHECK(lower == Approx(2.0f).margin(1.0f));
  }
  // The eyeballs moved with the opening's middle: up by about half a pixel.
  for (const glm::vec3& centre : features.eye_centres) {
    std::uint32_t nearest = 0;
    for (std::uint32_t v = 0; v < head.vertex_count(); ++v) {
      if (glm::distance(before[v], centre) < glm::distance(before[nearest], centre)) nearest = v;
    }
    CHECK(Project(camera, posed[nearest]).y - Project(camera, before[nearest]).y < -0.1f);
  }
  // The rest of the face stays; the rest face took the same offsets.
  for (const std::uint32_t v : {features.nose_tip, features.mouth_corners[0], features.mouth_corners[1]}) {
    CHECK(glm::distance(Project(camera, posed[v]), Project(camera, before[v])) < 0.05f);
  }
  for (std::size_t v = 0; v < posed.size(); ++v) REQUIRE(glm::distance(rest[v] - before[v], posed[v] - before[v]) < 1e-6f);
}

TEST_CASE("photo rig: closed eyes in the photo, or no eye openings near its landmarks, leave the lids", "[photo_rig]") {
  FrontHead front;
  auto& [features, head, surface, landmark_vertices, camera, posed, rest] = front;
  std::vector<glm::vec2> on_face;
  for (const std::uint32_t v : landmark_vertices) on_face.push_back(Project(camera, posed[v]));
  // Closed: every lid point on the line between its eye's corners.
  std::vector<glm::vec2> closed = on_face;
  for (const std::size_t first : {std::size_t{36}, std::size_t{42}}) {
    for (std::size_t k = 1; k < 6; ++k) {
      if (k == 3) continue;
      const float t = k < 3 ? static_cast<float>(k) / 3.0f : static_cast<float>(6 - k) / 3.0f;
      closed[first + k] = glm::mix(closed[first], closed[first + 3], t);
    }
  }
  // Far from the face: no rim lies near their eyes.
  std::vector<glm::vec2> aside = on_face;
  for (glm::vec2& p : aside) p.x += 200.0f;
  const std::vector<glm::vec3> before = posed;
  for (const std::vector<glm::vec2>* landmarks : {&closed, &aside}) {
    const LidMarginFit fit =
        FitLidMarginsToPhoto(surface, *landmarks, landmark_vertices, camera, kImageSize, kImageSize, posed, rest);
    CHECK(fit.eyes == 0);
    CHECK(posed == before);
    CHECK(rest == before);
  }
}

}  // namespace facerig
