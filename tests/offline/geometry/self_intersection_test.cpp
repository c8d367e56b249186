#include "facerig/offline/geometry/self_intersection.h"

#include <catch2/catch.hpp>
#include <cstdint>
#include <glm/geometric.hpp>
#include <random>
#include <vector>

#include "facerig/offline/transfer/deformation_transfer.h"
#include "support/test_meshes.h"
#include "facerig/offline/error.h"

namespace {

__extension__ typedef __int128 Int128;

struct Soup : facerig::Mesh {

  // A quad a b c d as triangles (a b c) and (a c d).
  void AddQuad(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    const auto base = static_cast<std::uint32_t>(positions.size());
    positions.insert(positions.end(), {a, b, c, d});
    triangles.push_back({base, base + 1, base + 2});
    triangles.push_back({base, base + 2, base + 3});
  }
  void AddTriangle(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    const auto base = static_cast<std::uint32_t>(positions.size());
    positions.insert(positions.end(), {a, b, c});
    triangles.push_back({base, base + 1, base + 2});
  }
  // Quad A in z = 0, diagonal y = x; quad B in y = 0.3, diagonal z = 2x. They cut
  // along y = 0.3, z = 0, x in [-0.5, 0.5]: A's diagonal splits that at x = 0.3,
  // B's at x = 0, so B's x < 0 half meets only A's upper triangle. Vertices
  // 0-3 are A's, 4-7 B's.
  void AddCrossingQuads() {
    AddQuad({-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
    AddQuad({-0.5f, 0.3f, -1}, {0.5f, 0.3f, -1}, {0.5f, 0.3f, 1}, {-0.5f, 0.3f, 1});
  }
};

std::size_t Count(const Soup& soup) {
  return facerig::FindSelfIntersections(soup).intersecting_pairs;
}

// The exact orientation of integer points (|coordinate| < 2^24, exact as floats).
int IntegerOrientSign(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d) {
  auto diff = [&](const glm::vec3& p, int k) { return static_cast<Int128>(p[k]) - static_cast<Int128>(d[k]); };
  const Int128 adx = diff(a, 0), ady = diff(a, 1), adz = diff(a, 2);
  const Int128 bdx = diff(b, 0), bdy = diff(b, 1), bdz = diff(b, 2);
  const Int128 cdx = diff(c, 0), cdy = diff(c, 1), cdz = diff(c, 2);
  const Int128 det = adz * (bdx * cdy - cdx * bdy) + bdz * (cdx * ady - adx * cdy) + cdz * (adx * bdy - bdx * ady);
  return (det > 0) - (det < 0);
}

}  // namespace

TEST_CASE("Two quads crossing each other: the three triangle pairs that cross", "[self_intersection]") {
  Soup soup;
  soup.AddCrossingQuads();
  facerig::SelfIntersectionParams params;
  params.max_pairs = 10;
  const facerig::SelfIntersectionResult result =
      facerig::FindSelfIntersections(soup, params);
  CHECK(result.intersecting_pairs == 3);
  REQUIRE(result.pairs.size() == 3);
  CHECK(result.pairs[0] == std::pair<std::uint32_t, std::uint32_t>{0, 2});
  CHECK(result.pairs[1] == std::pair<std::uint32_t, std::uint32_t>{1, 2});
  CHECK(result.pairs[2] == std::pair<std::uint32_t, std::uint32_t>{1, 3});
  CHECK(result.tested_triangles == 4);
  CHECK(result.degenerate_triangles == 0);
  // max_pairs limits the list, not the count.
  params.max_pairs = 1;
  const facerig::SelfIntersectionResult limited =
      facerig::FindSelfIntersections(soup, params);
  CHECK(limited.intersecting_pairs == 3);
  CHECK(limited.pairs.size() == 1);
  // Move B off A: nothing.
  for (std::size_t v = 4; v < 8; ++v) soup.positions[v].y += 1.5f;
  CHECK(Count(soup) == 0);
}

TEST_CASE("Crossing depth: how far the shallower side pokes through", "[self_intersection]") {
  // A lies in z = 0, reaching 1 and 2 to either side of B's plane x = 0; B stands
  // in x = 0 and pokes 0.3 below A's plane, 0.5 above.
  const glm::vec3 a1{-1, -1, 0}, a2{2, -1, 0}, a3{2, 2, 0};
  const glm::vec3 b1{0, 0.5f, -0.3f}, b2{0, 1.5f, 0.5f}, b3{0, -0.5f, 0.5f};
  CHECK(facerig::CrossingDepth(a1, a2, a3, b1, b2, b3) == Approx(0.3f));
  CHECK(facerig::CrossingDepth(b1, b2, b3, a1, a2, a3) == Approx(0.3f));  // symmetric
  // Deeper: B's low vertex 0.45 down, its two upper ones 0.5 up.
  CHECK(facerig::CrossingDepth(a1, a2, a3, b1 - glm::vec3(0, 0, 0.15f), b2, b3) == Approx(0.45f));
  // B lifted to rest on A's plane, or above it: no depth.
  const glm::vec3 lift{0, 0, 0.3f};
  CHECK(facerig::CrossingDepth(a1, a2, a3, b1 + lift, b2 + lift, b3 + lift) == 0.0f);
  CHECK(facerig::CrossingDepth(a1, a2, a3, b1 + 2.0f * lift, b2 + 2.0f * lift, b3 + 2.0f * lift) == 0.0f);
  // A degenerate triangle has no plane.
  CHECK(facerig::CrossingDepth(a1, a2, a1, b1, b2, b3) == 0.0f);
}

TEST_CASE("Touching without crossing does not count, a hair further in does", "[self_intersection]") {
  const glm::vec3 a{-1, -1, 0}, b{1, -1, 0}, c{1, 1, 0}, d{-1, 1, 0};
  SECTION("an edge resting on the other quad") {
    Soup soup;
    soup.AddQuad(a, b, c, d);
    soup.AddQuad({-0.5f, 0.3f, 0}, {0.5f, 0.3f, 0}, {0.5f, 0.3f, 1}, {-0.5f, 0.3f, 1});
    CHECK(Count(soup) == 0);
    for (std::size_t v = 4; v < 6; ++v) soup.positions[v].z = -1e-4f;
    CHECK(Count(soup) > 0);
  }
  SECTION("a vertex resting on the other triangle") {
    Soup soup;
    soup.AddTriangle(a, b, c);
    soup.AddTriangle({0.5f, -0.5f, 0}, {0.5f, -0.5f, 1}, {0.6f, 0.0f, 1});
    CHECK(Count(soup) == 0);
    soup.positions[3].z = -1e-3f;
    CHECK(Count(soup) == 1);
  }
  SECTION("a near miss") {
    Soup soup;
    soup.AddTriangle(a, b, c);
    soup.AddTriangle({0.5f, -0.5f, 1e-6f}, {0.5f, -0.5f, 1}, {0.6f, 0.0f, 1});
    CHECK(Count(soup) == 0);
  }
  SECTION("edges crossing at one point") {
    // Each triangle straddles the other's plane, but their cuts only meet at a point.
    Soup soup;
    soup.AddTriangle({0, 0, 0}, {2, 0, 0}, {0, 0, 2});   // y = 0 plane, edge x + z = 2
    soup.AddTriangle({1, -1, 1}, {1, 1, 1}, {3, 0, 3});  // passes x + z = 2 at (1, 0, 1)
    CHECK(Count(soup) == 0);
  }
}

TEST_CASE("Neighbours sharing a vertex or an edge are never counted", "[self_intersection]") {
  // B shares vertex 0 with A and its far edge pierces A's interior.
  Soup soup;
  soup.positions = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5f, 0.5f, -1}, {0.5f, 0.5f, 1}};
  soup.triangles = {{0, 1, 2}, {0, 3, 4}};
  CHECK(Count(soup) == 0);
  // The same geometry with vertex 0 duplicated (a seam): now a crossing.
  soup.positions.push_back(soup.positions[0]);
  soup.triangles[1] = {5, 3, 4};
  CHECK(Count(soup) == 1);
  // Two triangles on either side of an edge, sharing it (folded or flat): 0, also as a seam.
  Soup hinge;
  hinge.positions = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {0.5f, -1, 0.3f}, {0, 0, 0}, {1, 0, 0}};
  hinge.triangles = {{0, 1, 2}, {1, 0, 3}};
  CHECK(Count(hinge) == 0);
  hinge.triangles[1] = {5, 4, 3};
  CHECK(Count(hinge) == 0);
  // Folded back onto itself through the first triangle: the shared edge hides it.
  hinge.positions[3] = {0.5f, 0.9f, -0.01f};
  hinge.triangles[1] = {1, 0, 3};
  CHECK(Count(hinge) == 0);
}

TEST_CASE("Degenerate triangles have no plane and never count", "[self_intersection]") {
  Soup soup;
  soup.AddTriangle({-1, -1, 0}, {1, -1, 0}, {0, 1, 0});
  // A needle through the first triangle, collinear.
  soup.AddTriangle({0, 0, -1}, {0, 0, 0.5f}, {0, 0, 1});
  // A repeated vertex.
  soup.AddTriangle({0.1f, 0, -1}, {0.1f, 0, -1}, {0.1f, 0.1f, 1});
  const facerig::SelfIntersectionResult result = facerig::FindSelfIntersections(soup);
  CHECK(result.intersecting_pairs == 0);
  CHECK(result.degenerate_triangles == 2);
  CHECK(result.tested_triangles == 3);
  // Widen the needle into a real triangle: it crosses.
  soup.positions[4].x = 0.2f;
  CHECK(Count(soup) == 1);
}

TEST_CASE("Region: only triangles with every vertex in the range", "[self_intersection]") {
  Soup soup;
  soup.AddCrossingQuads();
  facerig::SelfIntersectionParams params;
  params.region_first = 0;
  params.region_last = 4;
  CHECK(facerig::FindSelfIntersections(soup, params).intersecting_pairs == 0);
  params.region_last = 8;
  CHECK(facerig::FindSelfIntersections(soup, params).intersecting_pairs == 3);
  params.region_first = 1;  // drops both triangles of A (they use vertex 0)
  const auto result = facerig::FindSelfIntersections(soup, params);
  CHECK(result.intersecting_pairs == 0);
  CHECK(result.tested_triangles == 2);
}

TEST_CASE("Invalid inputs: bad index or non-finite position", "[self_intersection]") {
  Soup soup;
  soup.AddTriangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  soup.triangles.push_back({0, 1, 7});
  CHECK_THROWS_AS(facerig::FindSelfIntersections(soup), facerig::InvalidInputError);
  soup.triangles.pop_back();
  soup.positions[1].x = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_AS(facerig::FindSelfIntersections(soup), facerig::InvalidInputError);
  CHECK(facerig::FindSelfIntersections(facerig::test::MeshOf({}, {})).intersecting_pairs == 0);
}

TEST_CASE("Exact orientation: coplanar integer points give 0, signs match 128-bit integers",
          "[self_intersection]") {
  // Coordinates up to 2^21 with differences multiplied to ~2^66: plain double
  // arithmetic rounds, the exact fallback must not.
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> coordinate(-(1 << 21), 1 << 21);
  std::uniform_int_distribution<int> step(-1, 2);
  auto point = [&] {
    return glm::vec3(static_cast<float>(coordinate(rng)), static_cast<float>(coordinate(rng)),
                     static_cast<float>(coordinate(rng)));
  };
  int zero = 0, matched = 0;
  for (int i = 0; i < 2000; ++i) {
    const glm::vec3 a = point(), b = point(), c = point();
    const float s = static_cast<float>(step(rng)), t = static_cast<float>(step(rng));
    const glm::vec3 d = a + s * (b - a) + t * (c - a);  // integers below 2^24: exact
    zero += facerig::Orient3dSign(a, b, c, d) == 0;
    const glm::vec3 e = d + glm::vec3(0.0f, 0.0f, static_cast<float>(1 + i % 3));
    matched += facerig::Orient3dSign(a, b, c, e) == IntegerOrientSign(a, b, c, e);
  }
  CHECK(zero == 2000);
  CHECK(matched == 2000);
}

TEST_CASE("Exact orientation is antisymmetric on nearly coplanar float points", "[self_intersection]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  int consistent = 0;
  for (int i = 0; i < 2000; ++i) {
    const glm::vec3 offset(1000.0f * unit(rng), 1000.0f * unit(rng), 1000.0f * unit(rng));
    const glm::vec3 a = offset + glm::vec3(unit(rng), unit(rng), unit(rng));
    const glm::vec3 b = offset + glm::vec3(unit(rng), unit(rng), unit(rng));
    const glm::vec3 c = offset + glm::vec3(unit(rng), unit(rng), unit(rng));
    const float s = unit(rng), t = unit(rng);
    const glm::vec3 d = a + s * (b - a) + t * (c - a);  // rounded onto a float near the plane
    const int sign = facerig::Orient3dSign(a, b, c, d);
    consistent += sign == -facerig::Orient3dSign(b, a, c, d) && sign == facerig::Orient3dSign(b, c, a, d) &&
                  sign == -facerig::Orient3dSign(d, b, c, a) && sign == facerig::Orient3dSign(c, a, b, d);
  }
  CHECK(consistent == 2000);
}

TEST_CASE("The grid finds exactly what testing every pair finds", "[self_intersection]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::normal_distribution<float> small(0.0f, 0.08f);
  Soup soup;
  for (int t = 0; t < 400; ++t) {
    const glm::vec3 centre(unit(rng), unit(rng), unit(rng));
    soup.AddTriangle(centre + glm::vec3(small(rng), small(rng), small(rng)),
                     centre + glm::vec3(small(rng), small(rng), small(rng)),
                     centre + glm::vec3(small(rng), small(rng), small(rng)));
  }
  // A few large triangles spanning many cells, and some sharing vertices.
  soup.AddTriangle({0, 0, 0.5f}, {1, 0, 0.5f}, {0, 1, 0.5f});
  soup.AddTriangle({1, 1, 0.2f}, {0, 1, 0.8f}, {1, 0, 0.6f});
  for (std::uint32_t t = 0; t + 1 < 40; t += 2) soup.triangles.push_back({3 * t, 3 * t + 4, 3 * t + 8});
  std::size_t brute = 0;
  for (std::size_t i = 0; i < soup.triangles.size(); ++i) {
    for (std::size_t j = i + 1; j < soup.triangles.size(); ++j) {
      const facerig::Triangle& ti = soup.triangles[i];
      const facerig::Triangle& tj = soup.triangles[j];
      bool shared = false;
      for (const std::uint32_t v : ti) shared = shared || v == tj[0] || v == tj[1] || v == tj[2];
      if (shared) continue;
      brute += facerig::TrianglesCross(soup.positions[ti[0]], soup.positions[ti[1]], soup.positions[ti[2]],
                                       soup.positions[tj[0]], soup.positions[tj[1]], soup.positions[tj[2]]);
    }
  }
  REQUIRE(brute > 50);  // the soup is dense enough to be a test
  CHECK(Count(soup) == brute);
  // The test is symmetric in the two triangles and in their vertex order.
  const auto& p = soup.positions;
  int symmetric = 0;
  for (std::size_t i = 0; i + 1 < 400; ++i) {
    const facerig::Triangle& a = soup.triangles[i];
    const facerig::Triangle& b = soup.triangles[i + 1];
    const bool x = facerig::TrianglesCross(p[a[0]], p[a[1]], p[a[2]], p[b[0]], p[b[1]], p[b[2]]);
    symmetric += x == facerig::TrianglesCross(p[b[0]], p[b[1]], p[b[2]], p[a[0]], p[a[1]], p[a[2]]) &&
                 x == facerig::TrianglesCross(p[a[1]], p[a[0]], p[a[2]], p[b[2]], p[b[0]], p[b[1]]);
  }
  CHECK(symmetric == 399);
}

TEST_CASE("ICT-FaceKit: the grid agrees with testing every pair around the mouth, timing (shared data)",
          "[self_intersection][shared-data]") {
  const facerig::Rig& rig = facerig::test::IctRig();
  // mouthClose alone pushes the lips through each other.
  const std::vector<glm::vec3> closed = facerig::RigExpressionMeshes(rig)[*rig.FindShape("mouthClose")];
  // Every triangle (all parts: lips, teeth, gums, mouth socket) with a vertex within 3 cm of the lips' centre.
  const glm::vec3 centre = 0.5f * (rig.positions()[5533] + rig.positions()[5517]);  // ICT landmarks 62, 66
  std::vector<facerig::Triangle> mouth;
  for (const facerig::Triangle& t : rig.triangles()) {
    if (glm::length(closed[t[0]] - centre) < 3.0f) mouth.push_back(t);
  }
  REQUIRE(mouth.size() > 2000);
  std::size_t brute = 0;
  for (std::size_t i = 0; i < mouth.size(); ++i) {
    for (std::size_t j = i + 1; j < mouth.size(); ++j) {
      const facerig::Triangle& a = mouth[i];
      const facerig::Triangle& b = mouth[j];
      if (a[0] == b[0] || a[0] == b[1] || a[0] == b[2] || a[1] == b[0] || a[1] == b[1] || a[1] == b[2] ||
          a[2] == b[0] || a[2] == b[1] || a[2] == b[2]) {
        continue;
      }
      brute += facerig::TrianglesCross(closed[a[0]], closed[a[1]], closed[a[2]], closed[b[0]], closed[b[1]],
                                       closed[b[2]]);
    }
  }
  const facerig::SelfIntersectionResult around_mouth = facerig::FindSelfIntersections(facerig::test::MeshOf(closed, mouth));
  CHECK(around_mouth.intersecting_pairs == brute);
  CHECK(brute > 100);

  // The whole rig (26,719 vertices, 52,220 triangles): issue 6 asks for well under 100 ms.
  const facerig::SelfIntersectionResult whole = facerig::FindSelfIntersections(facerig::NeutralMesh(rig));
  facerig::SelfIntersectionParams face;
  face.region_last = 9409;
  const facerig::SelfIntersectionResult face_only =
      facerig::FindSelfIntersections(facerig::NeutralMesh(rig), face);
  WARN("ICT neutral: " << whole.intersecting_pairs << " intersecting pairs in " << 1e3 * whole.seconds << " ms ("
                       << whole.candidate_pairs << " candidate pairs); the face alone "
                       << face_only.intersecting_pairs << " in " << 1e3 * face_only.seconds
                       << " ms; around the closed mouth " << brute << " of " << mouth.size() << " triangles");
  CHECK(whole.tested_triangles == rig.triangle_count());
  CHECK(whole.degenerate_triangles == 0);
}
