// Eye landmarks fitted to a mesh's eye openings (openings.h)
// on a sheet with an elliptical eye hole 2 wide and 0.8 tall, centred at
// (-3, 0), with an iris ring (a smaller hole of its own) inside it.
#include "facerig/offline/openings/eyes.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
#include <vector>

namespace {

constexpr int kAngles = 64;
const glm::vec3 kEyeCentre(-3.0f, 0.0f, 0.0f);

// Rings of an ellipse with half-axes (a r, b r) for each r in radii, joined
// into triangles: the first and last rings are the boundary loops.
void AddRings(std::vector<glm::vec3>& positions, std::vector<facerig::Triangle>& triangles, glm::vec3 centre,
              float a, float b, std::initializer_list<float> radii) {
  const auto first = static_cast<std::uint32_t>(positions.size());
  for (float r : radii) {
    for (int i = 0; i < kAngles; ++i) {
      const double angle = 2.0 * std::numbers::pi * i / kAngles;
      positions.push_back(centre + glm::vec3(a * r * std::cos(angle), b * r * std::sin(angle), 0.0f));
    }
  }
  for (std::uint32_t ring = 0; ring + 1 < radii.size(); ++ring) {
    for (std::uint32_t i = 0; i < kAngles; ++i) {
      const std::uint32_t j = (i + 1) % kAngles;
      const std::uint32_t inner = first + ring * kAngles, outer = inner + kAngles;
      triangles.push_back({inner + i, outer + i, outer + j});
      triangles.push_back({inner + i, outer + j, inner + j});
    }
  }
}

struct EyeMesh {
  std::vector<glm::vec3> positions;
  std::vector<facerig::Triangle> triangles;
};

EyeMesh MakeEyeMesh() {
  EyeMesh mesh;
  AddRings(mesh.positions, mesh.triangles, kEyeCentre, 1.0f, 0.4f, {1.0f, 1.5f, 2.5f, 4.0f});  // skin
  AddRings(mesh.positions, mesh.triangles, kEyeCentre - glm::vec3(0, 0, 0.2f), 0.5f, 0.5f, {0.9f, 1.2f});  // iris
  return mesh;
}

// The eye hole's margin at x: the point of the ellipse above or below.
glm::vec3 Margin(float x, bool upper) {
  const float u = (x - kEyeCentre.x) / 1.0f;
  const float y = 0.4f * std::sqrt(std::max(0.0f, 1.0f - u * u));
  return {x, upper ? y : -y, 0.0f};
}

// 68 landmarks, all far from the hole but those of the first eye (36-41).
std::vector<glm::vec3> Landmarks(glm::vec3 corner_first, glm::vec3 corner_last, float upper_y, float lower_y) {
  std::vector<glm::vec3> points(68, glm::vec3(20.0f, 20.0f, 0.0f));
  for (std::size_t k = 42; k < 48; ++k) points[k] = glm::vec3(3.0f + 0.3f * static_cast<float>(k - 42), 0.0f, 0.0f);
  points[36] = corner_first;
  points[37] = {-3.4f, upper_y, 0.0f};
  points[38] = {-2.6f, upper_y, 0.0f};
  points[39] = corner_last;
  points[40] = {-2.6f, lower_y, 0.0f};
  points[41] = {-3.4f, lower_y, 0.0f};
  return points;
}

}  // namespace

TEST_CASE("Eye openings: an eye the detector missed goes onto the opening's margins", "[eye_openings]") {
  const EyeMesh mesh = MakeEyeMesh();
  // Detected too wide and too high (as dlib on a stylized head).
  std::vector<glm::vec3> points = Landmarks({-4.4f, 0.3f, 0.0f}, {-1.6f, 0.3f, 0.0f}, 0.9f, 0.5f);
  const std::vector<glm::vec3> detected = points;
  CHECK(facerig::FitEyesToOpenings(mesh.positions, mesh.triangles, points).eyes == 1);
  // The skin's hole, not the iris ring's: the corners at its ends.
  CHECK(glm::length(points[36] - glm::vec3(-4.0f, 0.0f, 0.0f)) < 1e-4f);
  CHECK(glm::length(points[39] - glm::vec3(-2.0f, 0.0f, 0.0f)) < 1e-4f);
  // Lid points on the upper and lower margins, where the detector put them along the eye.
  const float spacing = 2.0f * std::numbers::pi_v<float> / kAngles;  // between loop vertices, at most
  CHECK(glm::length(points[37] - Margin(-3.4f, true)) < spacing);
  CHECK(glm::length(points[38] - Margin(-2.6f, true)) < spacing);
  CHECK(glm::length(points[40] - Margin(-2.6f, false)) < spacing);
  CHECK(glm::length(points[41] - Margin(-3.4f, false)) < spacing);
  // The other eye has no opening near it: unchanged.
  for (std::size_t k = 42; k < 48; ++k) CHECK(points[k] == detected[k]);
}

TEST_CASE("Eye openings: lid points near the margins are kept, the corners move", "[eye_openings]") {
  const EyeMesh mesh = MakeEyeMesh();
  std::vector<glm::vec3> points = Landmarks({-3.9f, 0.05f, 0.0f}, {-2.1f, 0.05f, 0.0f}, 0.42f, -0.3f);
  const std::vector<glm::vec3> detected = points;
  CHECK(facerig::FitEyesToOpenings(mesh.positions, mesh.triangles, points).eyes == 1);
  CHECK(glm::length(points[36] - glm::vec3(-4.0f, 0.0f, 0.0f)) < 1e-4f);
  CHECK(glm::length(points[39] - glm::vec3(-2.0f, 0.0f, 0.0f)) < 1e-4f);
  for (std::size_t k : {37, 38, 40, 41}) CHECK(points[k] == detected[k]);
}

TEST_CASE("Eye openings: no opening near the eyes changes nothing", "[eye_openings]") {
  EyeMesh mesh = MakeEyeMesh();
  for (glm::vec3& p : mesh.positions) p.y += 10.0f;  // the hole far above the detected eyes
  std::vector<glm::vec3> points = Landmarks({-4.0f, 0.0f, 0.0f}, {-2.0f, 0.0f, 0.0f}, 0.4f, -0.4f);
  const std::vector<glm::vec3> detected = points;
  CHECK(facerig::FitEyesToOpenings(mesh.positions, mesh.triangles, points).eyes == 0);
  CHECK(points == detected);
  CHECK(facerig::CorrectEyeCorners(mesh.positions, mesh.triangles, points) == 0);
}
