#include "facerig/runtime/rig_builder.h"

#include <limits>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "support/test_meshes.h"

using facerig::RawRig;
using facerig::RigBuilder;

namespace {
std::string ProblemOf(const RawRig& raw) {
  std::string problem;
  REQUIRE_FALSE(raw.Validate(&problem));
  REQUIRE_FALSE(RigBuilder::Build(raw));
  return problem;
}
}  // namespace

TEST_CASE("RigBuilder builds a rig with sorted sparse shapes and derived data", "[rig_builder]") {
  RawRig raw = facerig::test::MakeGridRawRig(4, 2);
  // Shuffle one shape's entries: the builder must sort them.
  std::swap(raw.shapes[0].vertex_indices.front(), raw.shapes[0].vertex_indices.back());
  std::swap(raw.shapes[0].position_deltas.front(), raw.shapes[0].position_deltas.back());
  const glm::vec3 delta_of_first = raw.shapes[0].position_deltas.back();
  std::string problem;
  const auto rig = RigBuilder::Build(raw, &problem);
  REQUIRE(rig);
  REQUIRE(rig->vertex_count() == 16);
  REQUIRE(rig->triangle_count() == 18);
  REQUIRE(rig->shape_count() == 2);
  REQUIRE(rig->shape_name(1) == "shape1");
  REQUIRE(rig->FindShape("shape1") == 1u);
  REQUIRE_FALSE(rig->FindShape("missing"));
  const facerig::BlendShapeView shape = rig->shape(0);
  for (std::size_t i = 1; i < shape.vertex_indices.size(); ++i) {
    REQUIRE(shape.vertex_indices[i - 1] < shape.vertex_indices[i]);
  }
  REQUIRE(shape.vertex_indices.front() == 0u);
  REQUIRE(shape.position_deltas.front() == delta_of_first);
  // Neutral normals computed: the grid lies in XY, so they are +Z.
  for (const glm::vec3& n : rig->normals()) REQUIRE(n.z == Approx(1.0f));
  REQUIRE(rig->bounding_diagonal() == Approx(std::sqrt(18.0f)));
  REQUIRE(rig->parts().size() == 2);
  REQUIRE(rig->FindPart("right")->first_triangle == 9u);
  REQUIRE(rig->FindPart("left")->first_vertex == 0u);
  REQUIRE(rig->units() == facerig::Units::kCentimetres);

  // ToRaw and back is the identity.
  const auto again = RigBuilder::Build(RigBuilder::ToRaw(*rig));
  REQUIRE(again);
  std::string difference;
  REQUIRE(facerig::test::RigsEqual(*rig, *again, 0.0f, &difference));
}

TEST_CASE("RigBuilder: a rig without parts gets one part covering all triangles", "[rig_builder]") {
  RawRig raw = facerig::test::MakeGridRawRig(3, 0);
  raw.parts.clear();
  const auto rig = RigBuilder::Build(raw);
  REQUIRE(rig);
  REQUIRE(rig->parts().size() == 1);
  REQUIRE(rig->parts()[0].triangle_count == rig->triangle_count());
}

TEST_CASE("RawRig::Validate names the first problem", "[rig_builder]") {
  const RawRig good = facerig::test::MakeGridRawRig(4, 2, true);
  REQUIRE(good.Validate());

  RawRig raw = good;
  raw.positions.clear();
  REQUIRE(ProblemOf(raw).find("no vertices") != std::string::npos);

  raw = good;
  raw.triangles[3][1] = 16;
  REQUIRE(ProblemOf(raw).find("triangle 3 uses vertex 16") != std::string::npos);

  raw = good;
  raw.positions[5].y = std::numeric_limits<float>::quiet_NaN();
  REQUIRE(ProblemOf(raw).find("position 5") != std::string::npos);

  raw = good;
  raw.uvs.pop_back();
  REQUIRE(ProblemOf(raw).find("UVs") != std::string::npos);

  raw = good;
  raw.shapes[1].vertex_indices[0] = 99;
  REQUIRE(ProblemOf(raw).find("shape 'shape1': vertex index 99") != std::string::npos);

  raw = good;
  raw.shapes[0].vertex_indices[1] = raw.shapes[0].vertex_indices[0];
  REQUIRE(ProblemOf(raw).find("appears twice") != std::string::npos);

  raw = good;
  raw.shapes[0].position_deltas[0].x = std::numeric_limits<float>::infinity();
  REQUIRE(ProblemOf(raw).find("not finite") != std::string::npos);

  raw = good;
  raw.shapes[1].normal_deltas.clear();
  REQUIRE(ProblemOf(raw).find("normal deltas") != std::string::npos);

  raw = good;
  raw.shapes[1].name = raw.shapes[0].name;
  REQUIRE(ProblemOf(raw).find("appears twice") != std::string::npos);

  raw = good;
  raw.parts[1].first_triangle += 1;
  REQUIRE(ProblemOf(raw).find("tile") != std::string::npos);
}

TEST_CASE("MakeSparseShape keeps only deltas above the threshold", "[rig_builder]") {
  const std::vector<glm::vec3> dense = {glm::vec3(0.0f), glm::vec3(0.5f, 0, 0), glm::vec3(1e-7f, 0, 0),
                                        glm::vec3(0, 0, -2.0f)};
  const facerig::RawBlendShape shape = facerig::MakeSparseShape("s", dense, {}, 1e-6f);
  REQUIRE(shape.vertex_indices == std::vector<std::uint32_t>{1, 3});
  REQUIRE(shape.position_deltas[1] == glm::vec3(0, 0, -2.0f));
  REQUIRE(shape.normal_deltas.empty());
  const std::vector<glm::vec3> normal_deltas = {glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.1f), glm::vec3(0.0f)};
  const facerig::RawBlendShape with_normals = facerig::MakeSparseShape("s", dense, normal_deltas, 1e-6f);
  REQUIRE(with_normals.vertex_indices == std::vector<std::uint32_t>{1, 2, 3});
}
