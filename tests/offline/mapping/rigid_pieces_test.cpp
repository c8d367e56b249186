#include "facerig/offline/mapping/rigid_pieces.h"

#include <algorithm>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "support/default_head_poses.h"

namespace facerig {
namespace {

RawRig RawGeometryOf(const Rig& rig) {
  RawRig raw;
  raw.positions.assign(rig.positions().begin(), rig.positions().end());
  raw.triangles.assign(rig.triangles().begin(), rig.triangles().end());
  for (const Part& part : rig.parts()) raw.parts.push_back({part.name, part.first_triangle, part.triangle_count});
  return raw;
}

std::vector<glm::vec3> ShapeDeltas(const Rig& rig, std::string_view name) {
  std::vector<glm::vec3> deltas(rig.vertex_count(), glm::vec3(0.0f));
  const BlendShapeView shape = rig.shape(*rig.FindShape(name));
  for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) deltas[shape.vertex_indices[i]] = shape.position_deltas[i];
  return deltas;
}

const Part& PartNamed(const Rig& rig, std::string_view name) {
  const Part* part = rig.FindPart(name);
  REQUIRE(part != nullptr);
  return *part;
}

}  // namespace

TEST_CASE("Rigid pieces: the built-in head's teeth and eyeballs are rigid pieces, its skin is not",
          "[rigid_pieces]") {
  const Rig& head = test::DefaultHead();
  const auto pieces = RigidPieces(RawGeometryOf(head));
  const Part& skin = PartNamed(head, "skin");
  std::size_t rigid_vertices = 0;
  for (const auto& piece : pieces) {
    rigid_vertices += piece.size();
    for (const std::uint32_t v : piece) CHECK((v < skin.first_vertex || v >= skin.first_vertex + skin.vertex_count));
  }
  std::size_t expected = 0;
  for (const char* name : {"eye_white_L", "eye_white_R", "iris_L", "iris_R", "pupil_L", "pupil_R", "teeth_upper",
                           "teeth_lower"}) {
    expected += PartNamed(head, name).vertex_count;
  }
  CHECK(rigid_vertices == expected);
}

TEST_CASE("Rigid pieces: an upper row whose vertices partly took the jaw's motion stays put", "[rigid_pieces]") {
  const Rig& head = test::DefaultHead();
  const RawRig raw = RawGeometryOf(head);
  const auto pieces = RigidPieces(raw);
  std::vector<glm::vec3> deltas = ShapeDeltas(head, "jawOpen");
  const Part& upper = PartNamed(head, "teeth_upper");
  const Part& lower = PartNamed(head, "teeth_lower");
  REQUIRE(deltas[lower.first_vertex] != glm::vec3(0.0f));
  // 40 % of the upper row follow the lower row, as a mapping onto the wrong gums gives.
  for (std::uint32_t i = 0; i < upper.vertex_count * 2 / 5; ++i) {
    deltas[upper.first_vertex + i] = deltas[lower.first_vertex + i % lower.vertex_count];
  }
  const std::vector<glm::vec3> before = deltas;
  MoveRigidPiecesRigidly(pieces, raw.positions, deltas);
  for (std::uint32_t v = upper.first_vertex; v < upper.first_vertex + upper.vertex_count; ++v) {
    CHECK(glm::length(deltas[v]) < 1e-4f);
  }
  // The skin is not a rigid piece: unchanged.
  const Part& skin = PartNamed(head, "skin");
  for (std::uint32_t v = skin.first_vertex; v < skin.first_vertex + skin.vertex_count; ++v) {
    REQUIRE(deltas[v] == before[v]);
  }
}

TEST_CASE("Rigid pieces: a lower row keeps the jaw's turn when a fifth of it stayed behind", "[rigid_pieces]") {
  const Rig& head = test::DefaultHead();
  const RawRig raw = RawGeometryOf(head);
  const auto pieces = RigidPieces(raw);
  const std::vector<glm::vec3> jaw = ShapeDeltas(head, "jawOpen");
  std::vector<glm::vec3> deltas = jaw;
  const Part& lower = PartNamed(head, "teeth_lower");
  float largest = 0.0f;
  for (std::uint32_t v = lower.first_vertex; v < lower.first_vertex + lower.vertex_count; ++v) {
    largest = std::max(largest, glm::length(jaw[v]));
  }
  REQUIRE(largest > 1.0f);  // centimetres: the jaw opens
  for (std::uint32_t i = 0; i < lower.vertex_count / 5; ++i) deltas[lower.first_vertex + 5 * i] = glm::vec3(0.0f);
  MoveRigidPiecesRigidly(pieces, raw.positions, deltas);
  float worst = 0.0f;
  for (std::uint32_t v = lower.first_vertex; v < lower.first_vertex + lower.vertex_count; ++v) {
    worst = std::max(worst, glm::length(deltas[v] - jaw[v]));
  }
  CHECK(worst < 0.01f * largest);
}

}  // namespace facerig
