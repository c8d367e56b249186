#include "facerig/offline/openings/gaps.h"
#include "facerig/offline/transfer/deformation_transfer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <random>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "facerig/runtime/io/obj.h"
#include "measure/expression_error.h"
#include "measure/ict_vertex_ranges.h"
#include "support/slit_sheet.h"
#include "support/test_meshes.h"

namespace {

using Meshes = std::vector<std::vector<glm::vec3>>;

namespace ict = facerig::test::ict;

using TinyMesh = facerig::Mesh;

TinyMesh Tetrahedron() {
  return {{{0.0f, 0.0f, 0.0f}, {1.0f, 0.1f, 0.0f}, {0.2f, 1.0f, 0.1f}, {0.3f, 0.2f, 1.0f}},
          {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
}

// An n x n grid in XY with a bump in z (so frames are not all parallel).
TinyMesh Grid(int n, float bump) {
  TinyMesh mesh;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const float fx = static_cast<float>(x);
      const float fy = static_cast<float>(y);
      mesh.positions.emplace_back(fx, fy, bump * std::sin(0.7f * fx) * std::cos(0.5f * fy));
    }
  }
  auto at = [n](int x, int y) { return static_cast<std::uint32_t>(y * n + x); };
  for (int y = 0; y + 1 < n; ++y) {
    for (int x = 0; x + 1 < n; ++x) {
      mesh.triangles.push_back({at(x, y), at(x + 1, y), at(x + 1, y + 1)});
      mesh.triangles.push_back({at(x, y), at(x + 1, y + 1), at(x, y + 1)});
    }
  }
  return mesh;
}

// The slit sheet (support/slit_sheet.h) and its blink closing the slit.
TinyMesh SlitGrid() {
  facerig::test::SlitSheet sheet = facerig::test::MakeSlitSheet();
  return {std::move(sheet.positions), std::move(sheet.triangles)};
}

std::vector<glm::vec3> CloseSlit(const TinyMesh& mesh) {
  std::vector<glm::vec3> expression = mesh.positions;
  const std::vector<glm::vec3> blink = facerig::test::SlitBlinkDeltas();
  for (std::size_t v = 0; v < expression.size(); ++v) expression[v] += blink[v];
  return expression;
}

float MaxDistance(std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
  REQUIRE(a.size() == b.size());
  float worst = 0.0f;
  for (std::size_t v = 0; v < a.size(); ++v) worst = std::max(worst, glm::length(a[v] - b[v]));
  return worst;
}

glm::mat3 RotationZ(float angle) {
  const float c = std::cos(angle);
  const float s = std::sin(angle);
  return glm::mat3(c, s, 0.0f, -s, c, 0.0f, 0.0f, 0.0f, 1.0f);  // column-major
}

// The ICT template and its 20 identity modes, read once per binary.
struct IctData {
  Meshes expressions;
  Meshes identities;
};

IctData ReadIctData() {
  IctData data;
  data.expressions = facerig::RigExpressionMeshes(facerig::test::IctRig());
  for (int k = 0; k < 20; ++k) {
    char name[32];
    std::snprintf(name, sizeof(name), "identity%03d.obj", k);
    data.identities.push_back(facerig::ReadObj(facerig::test::IctDir() / name).positions);
  }
  return data;
}

const IctData& Ict() {
  static const IctData data = ReadIctData();  // initialised once, thread-safe
  return data;
}

// A random same-topology ICT face: neutral + sum_i w_i (identity_i - neutral), w ~ N(0, 1).
std::vector<glm::vec3> RandomIctFace(unsigned seed) {
  const facerig::Rig& rig = facerig::test::IctRig();
  std::mt19937 rng(seed);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  std::vector<glm::vec3> face(rig.positions().begin(), rig.positions().end());
  for (const std::vector<glm::vec3>& identity : Ict().identities) {
    REQUIRE(identity.size() == face.size());
    const float w = normal(rng);
    for (std::size_t v = 0; v < face.size(); ++v) face[v] += w * (identity[v] - rig.positions()[v]);
  }
  return face;
}

// True expressions of a random face: T_i = T_0 + (S_i - S_0).
Meshes TrueExpressions(std::span<const glm::vec3> face) {
  const facerig::Rig& rig = facerig::test::IctRig();
  Meshes truth(Ict().expressions.size());
  for (std::size_t s = 0; s < truth.size(); ++s) {
    truth[s].assign(face.begin(), face.end());
    for (std::size_t v = 0; v < face.size(); ++v) {
      truth[s][v] += Ict().expressions[s][v] - rig.positions()[v];
    }
  }
  return truth;
}

struct ErrorTable {
  std::vector<double> errors;
  std::vector<double> leaks;
  std::string worst_shape;
  double worst = 0.0;
  double median() const { return facerig::Percentile(errors, 0.5); }
  double p90() const { return facerig::Percentile(errors, 0.9); }
};

ErrorTable Measure(const Meshes& result, const Meshes& truth, std::span<const glm::vec3> face) {
  const facerig::Rig& rig = facerig::test::IctRig();
  ErrorTable table;
  for (std::size_t s = 0; s < result.size(); ++s) {
    const facerig::ExpressionError e =
        facerig::MeasureExpressionError(face, truth[s], result[s], 0, ict::kFace.end);
    table.errors.push_back(e.relative_error);
    table.leaks.push_back(e.leak);
    if (e.relative_error > table.worst) {
      table.worst = e.relative_error;
      table.worst_shape = std::string(rig.shape_name(s));
    }
  }
  return table;
}

}  // namespace

TEST_CASE("Transferring no deformation returns the target unchanged", "[deformation_transfer]") {
  const TinyMesh source = Grid(7, 0.3f);
  const TinyMesh target = Grid(7, -0.5f);
  for (facerig::TransferMode mode :
       {facerig::TransferMode::kClassic, facerig::TransferMode::kIdentityGradient}) {
    facerig::DeformationTransferParams params;
    params.mode = mode;
    params.anchor_vertices = {0};
    const Meshes expressions{source.positions};
    const facerig::DeformationTransferResult result = facerig::DeformationTransfer(source, target.positions, expressions, params);
    REQUIRE(result.expressions.size() == 1);
    CHECK(MaxDistance(result.expressions[0], target.positions) < 1e-5f);
    CHECK(result.residuals[0] < 1e-5);
  }
}

TEST_CASE("A rotation of the source transfers exactly", "[deformation_transfer]") {
  const TinyMesh source = Tetrahedron();
  TinyMesh target = Tetrahedron();
  target.positions[2] += glm::vec3(0.2f, 0.3f, -0.1f);
  target.positions[3] *= 1.4f;
  const glm::mat3 rotation = RotationZ(0.6f) * glm::mat3(1.0f, 0.0f, 0.0f, 0.0f, 0.8f, 0.6f, 0.0f, -0.6f, 0.8f);
  Meshes expressions(1);
  // Rotated about vertex 0, which is the anchor (so it does not move).
  for (const glm::vec3& p : source.positions) expressions[0].push_back(rotation * p);
  facerig::DeformationTransferParams params;
  params.anchor_vertices = {0};
  params.displacement_prior = 0.0;  // pure deformation transfer: the prior pulls towards the deltas
  for (bool scaled_normal : {false, true}) {
    params.scaled_normal = scaled_normal;
    const facerig::DeformationTransferResult result = facerig::DeformationTransfer(source, target.positions, expressions, params);
    std::vector<glm::vec3> expected;
    for (const glm::vec3& p : target.positions) expected.push_back(rotation * p);
    CHECK(MaxDistance(result.expressions[0], expected) < 1e-5f);
  }
}

TEST_CASE("A uniform scale of the source transfers exactly with the 4th-vertex frames",
          "[deformation_transfer]") {
  const TinyMesh source = Tetrahedron();
  TinyMesh target = Tetrahedron();
  target.positions[1] += glm::vec3(0.3f, -0.2f, 0.2f);
  Meshes expressions(1);
  const glm::vec3 centre = source.positions[0];
  for (const glm::vec3& p : source.positions) expressions[0].push_back(centre + 1.5f * (p - centre));
  facerig::DeformationTransferParams params;
  params.anchor_vertices = {0};
  params.displacement_prior = 0.0;  // pure deformation transfer
  params.scaled_normal = true;  // the normal scales like the edges: the gradient is exactly 1.5 I
  const facerig::DeformationTransferResult result = facerig::DeformationTransfer(source, target.positions, expressions, params);
  std::vector<glm::vec3> expected;
  for (const glm::vec3& p : target.positions) {
    expected.push_back(target.positions[0] + 1.5f * (p - target.positions[0]));
  }
  CHECK(MaxDistance(result.expressions[0], expected) < 1e-5f);
}

TEST_CASE("Precompute once, solve per expression, threads do not change the result",
          "[deformation_transfer]") {
  const TinyMesh source = Grid(9, 0.4f);
  const TinyMesh target = Grid(9, 0.1f);
  Meshes expressions;
  for (int k = 0; k < 5; ++k) {
    std::vector<glm::vec3> e = source.positions;
    for (std::size_t v = 0; v < e.size(); ++v) {
      if (e[v].y > 2.5f) e[v].z += 0.2f * static_cast<float>(k + 1) * std::sin(e[v].x + static_cast<float>(k));
    }
    expressions.push_back(std::move(e));
  }
  facerig::DeformationTransferParams params;
  params.threads = 1;
  const facerig::DeformationTransferResult one = facerig::DeformationTransfer(source, target.positions, expressions, params);
  params.threads = 2;
  const facerig::DeformationTransferResult two = facerig::DeformationTransfer(source, target.positions, expressions, params);
  // Static anchors: the rows y <= 2 that no expression moves.
  CHECK(one.anchor_count == 27);
  facerig::DeformationTransferData data;
  facerig::PrecomputeDeformationTransfer(source, target.positions,
                                         expressions, params, data);
  CHECK(data.free_count == 81 - 27);
  for (std::size_t k = 0; k < expressions.size(); ++k) {
    CHECK(one.expressions[k] == two.expressions[k]);  // bit-identical
    std::vector<glm::vec3> single;
    const double residual = facerig::SolveDeformationTransfer(data, expressions[k], single);
    CHECK(single == one.expressions[k]);
    CHECK(residual == one.residuals[k]);
    for (std::size_t v = 0; v < 27; ++v) CHECK(single[v] == target.positions[v]);
  }
}

TEST_CASE("The displacement prior moves the result towards displacement transfer",
          "[deformation_transfer]") {
  const TinyMesh source = Grid(8, 0.3f);
  TinyMesh target = Grid(8, 0.1f);
  for (glm::vec3& p : target.positions) p.x *= 1.3f;  // wider: gradients differ from deltas
  Meshes expressions{source.positions};
  for (glm::vec3& p : expressions[0]) p.z += 0.3f * std::sin(p.x) * p.y;
  std::vector<glm::vec3> additive = target.positions;
  for (std::size_t v = 0; v < additive.size(); ++v) additive[v] += expressions[0][v] - source.positions[v];
  facerig::DeformationTransferParams params;
  params.anchor_vertices = {0};
  float previous = 1e30f;
  for (double prior : {0.0, 0.01, 1.0, 100.0}) {
    params.displacement_prior = prior;
    const facerig::DeformationTransferResult result = facerig::DeformationTransfer(source, target.positions, expressions, params);
    const float distance = MaxDistance(result.expressions[0], additive);
    CHECK(distance <= previous);
    previous = distance;
  }
  CHECK(previous < 0.01f);
  params.displacement_prior = -1.0;
  CHECK_THROWS_AS(facerig::DeformationTransfer(source, target.positions,
                                               expressions, params),
                  facerig::MeshInputError);
}

TEST_CASE("A part without anchors follows the template's mean displacement",
          "[deformation_transfer]") {
  // Two tetrahedra; anchors only on the first. The second moves as a whole.
  TinyMesh mesh = Tetrahedron();
  for (int v = 0; v < 4; ++v) mesh.positions.push_back(mesh.positions[static_cast<std::size_t>(v)] + glm::vec3(3.0f, 0.0f, 0.0f));
  for (int t = 0; t < 4; ++t) {
    facerig::Triangle tri = mesh.triangles[static_cast<std::size_t>(t)];
    for (std::uint32_t& v : tri) v += 4;
    mesh.triangles.push_back(tri);
  }
  TinyMesh target = mesh;
  for (glm::vec3& p : target.positions) p *= 1.1f;
  Meshes expressions{mesh.positions};
  const glm::vec3 shift(0.5f, -1.0f, 2.0f);
  for (std::size_t v = 4; v < 8; ++v) expressions[0][v] += shift;
  facerig::DeformationTransferParams params;
  params.anchor_vertices = {0, 1};
  const facerig::DeformationTransferResult result = facerig::DeformationTransfer(mesh, target.positions, expressions, params);
  CHECK(result.floating_components == 1);
  for (std::size_t v = 0; v < 8; ++v) {
    const glm::vec3 expected = target.positions[v] + (v >= 4 ? shift : glm::vec3(0.0f));
    CHECK(glm::length(result.expressions[0][v] - expected) < 1e-5f);
  }
}

TEST_CASE("What the template leaves still stays still, without static anchors", "[deformation_transfer]") {
  // One expression lifts the rows y > 2.5 of a bumpy grid; the only anchor is vertex 0.
  const TinyMesh source = Grid(9, 0.4f);
  TinyMesh target = Grid(9, 0.1f);
  for (glm::vec3& p : target.positions) p.x *= 1.2f;
  Meshes expressions{source.positions};
  for (glm::vec3& p : expressions[0]) {
    if (p.y > 2.5f) p.z += 0.3f * (p.y - 2.5f) * std::sin(p.x);
  }
  facerig::DeformationTransferParams params;
  params.anchor_vertices = {0};
  const facerig::DeformationTransferResult pinned = facerig::DeformationTransfer(source, target.positions, expressions, params);
  params.still_fraction = 0.0;
  const facerig::DeformationTransferResult gradient_only = facerig::DeformationTransfer(source, target.positions, expressions, params);
  float pinned_leak = 0.0f;
  float gradient_leak = 0.0f;
  for (std::size_t v = 0; v < target.positions.size(); ++v) {
    if (source.positions[v].y > 2.5f) continue;
    pinned_leak = std::max(pinned_leak, glm::length(pinned.expressions[0][v] - target.positions[v]));
    gradient_leak = std::max(gradient_leak, glm::length(gradient_only.expressions[0][v] - target.positions[v]));
  }
  CHECK(pinned_leak == 0.0f);
  CHECK(gradient_leak > 1e-3f);  // one anchor: the gradient mismatch moves the still rows
  params.still_fraction = 1.0;
  CHECK_THROWS_AS(facerig::DeformationTransfer(source, target.positions,
                                               expressions, params),
                  facerig::MeshInputError);
}

TEST_CASE("The result says whether contacts acted and how many pairs each expression kept",
          "[deformation_transfer]") {
  const TinyMesh source = SlitGrid();
  REQUIRE(source.triangles.size() == 2 * 10 * 6 - 2 * 6);
  std::vector<glm::vec3> target = source.positions;
  for (glm::vec3& p : target) p.y *= 1.2f;  // a taller slit
  const Meshes expressions{source.positions, CloseSlit(source)};
  facerig::DeformationTransferParams params;
  const facerig::DeformationTransferResult with_contacts =
      facerig::DeformationTransfer(source, target, expressions, params);
  CHECK(with_contacts.contacts_active);
  // The neutral closes nothing; the slit's 5 moving upper-edge vertices each meet the one below.
  CHECK(with_contacts.contact_counts == std::vector<std::size_t>{0, 5});

  SECTION("contact_weight 0 turns them off") { params.contact_weight = 0.0; }
  SECTION("without still pinning they cannot act, and the result says so") { params.still_fraction = 0.0; }
  const facerig::DeformationTransferResult without =
      facerig::DeformationTransfer(source, target, expressions, params);
  CHECK_FALSE(without.contacts_active);
  CHECK(without.contact_counts == std::vector<std::size_t>{0, 0});
}

TEST_CASE("Contacts close the slit on a taller target, or keep the template's offset",
          "[deformation_transfer]") {
  const TinyMesh source = SlitGrid();
  std::vector<glm::vec3> target = source.positions;
  for (glm::vec3& p : target) p.y *= 1.3f;  // a taller slit: gradients alone stop short
  const Meshes expressions{CloseSlit(source)};
  // The widest gap between the slit's moving upper edge (y = 4, 2 < x < 8) and the vertex below.
  const auto widest_gap = [&](const std::vector<glm::vec3>& result) {
    float widest = 0.0f;
    for (std::uint32_t x = 3; x < 8; ++x) {
      widest = std::max(widest, glm::length(result[4 * 11 + x] - result[3 * 11 + x]));
    }
    return widest;
  };
  facerig::DeformationTransferParams params;
  const float closed = widest_gap(
      facerig::DeformationTransfer(source, target, expressions, params).expressions[0]);
  params.close_contacts = false;
  const float kept = widest_gap(
      facerig::DeformationTransfer(source, target, expressions, params).expressions[0]);
  params.contact_weight = 0.0;
  const float without = widest_gap(
      facerig::DeformationTransfer(source, target, expressions, params).expressions[0]);
  WARN("slit gap after closing: closed " << closed << ", template offset kept " << kept << ", no contacts "
                                         << without << " (template 0.02)");
  // Measured: 0.008, 0.027, 0.19 (the contacts are soft, weight 10).
  CHECK(closed < 0.01f);
  CHECK(closed < kept - 0.015f);
  CHECK(std::abs(kept - 0.02f) < 0.01f);
  CHECK(without > 0.1f);
}

TEST_CASE("Parts the template moves by one rigid motion move rigidly together", "[deformation_transfer]") {
  // A static sheet (the skull) and two tetrahedra (a tooth and a gum) that the
  // expression turns about a common pivot (the jaw hinge).
  TinyMesh mesh = Grid(4, 0.2f);
  const std::uint32_t sheet = static_cast<std::uint32_t>(mesh.positions.size());
  const TinyMesh tetrahedron = Tetrahedron();
  for (int copy = 0; copy < 2; ++copy) {
    const auto first = static_cast<std::uint32_t>(mesh.positions.size());
    for (const glm::vec3& p : tetrahedron.positions) {
      mesh.positions.push_back(p + glm::vec3(0.5f + 1.5f * static_cast<float>(copy), -3.0f, 0.0f));
    }
    for (facerig::Triangle t : tetrahedron.triangles) {
      for (std::uint32_t& v : t) v += first;
      mesh.triangles.push_back(t);
    }
  }
  const glm::mat3 turn = RotationZ(0.3f);
  const glm::vec3 pivot(1.0f, 0.0f, 0.0f);
  Meshes expressions{mesh.positions};
  for (std::size_t v = sheet; v < mesh.positions.size(); ++v) {
    expressions[0][v] = pivot + turn * (mesh.positions[v] - pivot);
  }
  // The target's tooth is bigger and sits lower: the two are not a copy of the template's.
  TinyMesh target = mesh;
  for (std::size_t v = sheet; v < sheet + 4; ++v) target.positions[v] = 1.3f * target.positions[v] + glm::vec3(0.0f, 0.4f, 0.0f);
  facerig::DeformationTransferParams params;
  params.anchor_vertices = {0, 1, 2};
  const facerig::DeformationTransferResult result = facerig::DeformationTransfer(mesh, target.positions, expressions, params);
  const std::vector<glm::vec3>& moved = result.expressions[0];
  // One rigid motion for both parts: every distance between their vertices is kept.
  float worst_stretch = 0.0f;
  glm::vec3 mean_displacement(0.0f);
  glm::vec3 template_mean(0.0f);
  for (std::size_t a = sheet; a < moved.size(); ++a) {
    for (std::size_t b = sheet; b < a; ++b) {
      worst_stretch = std::max(worst_stretch, std::abs(glm::length(moved[a] - moved[b]) -
                                                       glm::length(target.positions[a] - target.positions[b])));
    }
    mean_displacement += (moved[a] - target.positions[a]) / 8.0f;
    template_mean += (expressions[0][a] - mesh.positions[a]) / 8.0f;
  }
  CHECK(worst_stretch < 1e-5f);
  // The template's rotation, and its mean displacement.
  const glm::vec3 edge = moved[sheet + 5] - moved[sheet + 4];
  const glm::vec3 rest_edge = target.positions[sheet + 5] - target.positions[sheet + 4];
  CHECK(glm::length(edge - turn * rest_edge) < 1e-5f);
  CHECK(glm::length(mean_displacement - template_mean) < 1e-5f);
  for (std::size_t v = 0; v < sheet; ++v) CHECK(moved[v] == target.positions[v]);
  // Each part placed on its own (rigid_tolerance 0: gradients, then its own
  // mean displacement) moves them apart.
  params.rigid_tolerance = 0.0;
  const facerig::DeformationTransferResult separate = facerig::DeformationTransfer(mesh, target.positions, expressions, params);
  const float apart = glm::length(separate.expressions[0][sheet] - separate.expressions[0][sheet + 4]);
  const float together = glm::length(moved[sheet] - moved[sheet + 4]);
  const float rest = glm::length(target.positions[sheet] - target.positions[sheet + 4]);
  CHECK(std::abs(together - rest) < 1e-5f);
  CHECK(std::abs(apart - rest) > 1e-3f);
}

TEST_CASE("Degenerate and needle triangles are regularized, not fatal", "[deformation_transfer]") {
  TinyMesh source = Grid(6, 0.2f);
  // Collapse one triangle to a point and squash another into a needle.
  source.positions[7] = source.positions[8];
  source.positions[15].y = source.positions[14].y + 1e-6f;
  TinyMesh target = source;
  for (glm::vec3& p : target.positions) p.z *= 2.0f;
  Meshes expressions{source.positions};
  for (glm::vec3& p : expressions[0]) p.z += 0.1f * p.x;
  facerig::DeformationTransferParams params;
  params.anchor_vertices = {0};
  const facerig::DeformationTransferResult result = facerig::DeformationTransfer(source, target.positions, expressions, params);
  CHECK(result.regularized_triangles >= 2);
  for (const glm::vec3& p : result.expressions[0]) {
    CHECK((std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)));
  }
  // Away from the bad triangles the shear still transfers: the far corner moves up.
  CHECK(result.expressions[0][35].z - target.positions[35].z > 0.3f);
}

TEST_CASE("Invalid inputs throw typed errors naming the mesh", "[deformation_transfer]") {
  const TinyMesh source = Grid(4, 0.1f);
  const Meshes expressions{source.positions};
  std::vector<glm::vec3> short_target(source.positions.begin(), source.positions.end() - 1);
  try {
    facerig::DeformationTransfer(source, short_target, expressions);
    FAIL("no exception");
  } catch (const facerig::MeshInputError& error) {
    CHECK(error.mesh() == "target neutral");
    CHECK(std::string(error.what()).find("15 vertices, expected 16") != std::string::npos);
  }
  const Meshes bad_expression{short_target};
  try {
    facerig::DeformationTransfer(source, source.positions, bad_expression);
    FAIL("no exception");
  } catch (const facerig::MeshInputError& error) {
    CHECK(error.mesh() == "source expression 0");
  }
  facerig::DeformationTransferParams params;
  params.anchor_vertices = {99};
  CHECK_THROWS_AS(facerig::DeformationTransfer(source, source.positions,
                                               expressions, params),
                  facerig::MeshInputError);
  std::vector<facerig::Triangle> bad_triangles = source.triangles;
  bad_triangles[3][1] = 16;
  CHECK_THROWS_AS(facerig::DeformationTransfer(facerig::test::MeshOf(source.positions, bad_triangles), source.positions,
                                               expressions),
                  facerig::InvalidInputError);
  std::vector<glm::vec3> nan_target = source.positions;
  nan_target[5].x = std::nanf("");
  CHECK_THROWS_AS(facerig::DeformationTransfer(source, nan_target, expressions),
                  facerig::MeshInputError);
  facerig::DeformationTransferData data;
  std::vector<glm::vec3> out;
  CHECK_THROWS_AS(facerig::SolveDeformationTransfer(data, source.positions, out),
                  facerig::MeshInputError);
}

TEST_CASE("A negative, NaN or infinite contact_weight is refused, naming it", "[deformation_transfer]") {
  // A transfer that keeps contacts when the weight is valid (still pinning on, a slit closing).
  const TinyMesh source = SlitGrid();
  const Meshes expressions{CloseSlit(source)};
  facerig::DeformationTransferParams params;
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  for (const double weight : {-1.0, std::numeric_limits<double>::quiet_NaN(), kInfinity, -kInfinity}) {
    INFO("contact_weight " << weight);
    params.contact_weight = weight;
    try {
      facerig::DeformationTransfer(source, source.positions, expressions, params);
      FAIL_CHECK("no exception");
    } catch (const facerig::MeshInputError& error) {
      CHECK(error.mesh() == "params");
      CHECK(std::string(error.what()).find("contact_weight") != std::string::npos);
    } catch (const std::exception& error) {
      FAIL_CHECK("not a MeshInputError: " << error.what());
    }
  }
  params.contact_weight = 0.0;  // off, not an error
  CHECK_NOTHROW(facerig::DeformationTransfer(source, source.positions, expressions,
                                             params));
}

TEST_CASE("TransferRig builds a rig with the template's shapes on the target", "[deformation_transfer]") {
  const facerig::Rig grid = facerig::test::MakeGridRig(8, 4);
  std::vector<glm::vec3> target(grid.positions().begin(), grid.positions().end());
  for (glm::vec3& p : target) p = 1.2f * p + glm::vec3(0.0f, 0.0f, 0.05f * p.x * p.y);
  facerig::DeformationTransferParams params;
  params.anchor_vertices = {0, 7};
  facerig::DeformationTransferResult result;
  facerig::RawRig raw = facerig::TransferRig(grid, target, params, &result);
  std::string problem;
  std::optional<facerig::Rig> rig = facerig::RigBuilder::Build(std::move(raw), &problem);
  REQUIRE(rig.has_value());
  CHECK(rig->shape_count() == grid.shape_count());
  CHECK(rig->shape_name(2) == grid.shape_name(2));
  CHECK(rig->positions()[5] == target[5]);
  CHECK(result.expressions.size() == 4);
}

TEST_CASE("Classic deformation transfer of the ICT rig onto random identities (shared data)",
          "[deformation_transfer][shared-data][accuracy]") {
  const facerig::Rig& rig = facerig::test::IctRig();
  ErrorTable classic_all;
  ErrorTable identity_all;
  for (unsigned seed : {7u, 8u, 9u}) {
    const std::vector<glm::vec3> face = RandomIctFace(seed);
    const Meshes truth = TrueExpressions(face);
    facerig::DeformationTransferParams params;
    const facerig::DeformationTransferResult classic =
        facerig::DeformationTransfer(facerig::NeutralMesh(rig), face, Ict().expressions, params);
    params.mode = facerig::TransferMode::kIdentityGradient;
    const facerig::DeformationTransferResult identity =
        facerig::DeformationTransfer(facerig::NeutralMesh(rig), face, Ict().expressions, params);
    REQUIRE(classic.expressions.size() == 53);
    const ErrorTable classic_errors = Measure(classic.expressions, truth, face);
    const ErrorTable identity_errors = Measure(identity.expressions, truth, face);
    WARN("face " << seed << ": classic median " << classic_errors.median() << " p90 "
                 << classic_errors.p90() << " worst " << classic_errors.worst_shape << " "
                 << classic_errors.worst << "; identity gradient median " << identity_errors.median()
                 << " p90 " << identity_errors.p90() << " worst " << identity_errors.worst_shape << " "
                 << identity_errors.worst << "; " << classic.precompute_seconds + classic.solve_seconds
                 << " s");
    for (const ErrorTable* from : {&classic_errors, &identity_errors}) {
      ErrorTable& into = from == &classic_errors ? classic_all : identity_all;
      into.errors.insert(into.errors.end(), from->errors.begin(), from->errors.end());
      into.leaks.insert(into.leaks.end(), from->leaks.begin(), from->leaks.end());
    }
    // Every part is anchored: the jaw's teeth follow jawOpen instead of flying off.
    CHECK(classic.floating_components > 0);
    const std::size_t jaw = *rig.FindShape("jawOpen");
    const facerig::ExpressionError teeth = facerig::MeasureExpressionError(
        face, truth[jaw], classic.expressions[jaw], ict::kTeeth.begin, ict::kTeeth.end);
    CHECK(teeth.relative_error < 0.1);
    // Parts without static vertices (eyeballs, teeth) match the template's mean
    // displacement, so nothing drifts off: the worst vertex error stays small.
    for (std::size_t s = 0; s < 53; ++s) {
      const facerig::ExpressionError whole =
          facerig::MeasureExpressionError(face, truth[s], classic.expressions[s], 0, face.size());
      INFO(rig.shape_name(s));
      CHECK(whole.max_error < 0.02 * rig.bounding_diagonal());
    }
  }
  WARN("3 faces: classic median " << classic_all.median() << " p90 " << classic_all.p90()
                                  << " (issue 6 targets 0.05 / 0.08), identity gradient median "
                                  << identity_all.median() << " p90 " << identity_all.p90());
  // Issue 6's targets. Measured on these 3 faces (not the bench's seeds, on
  // which the prior's weight was chosen): 0.043 / 0.073; without the
  // displacement prior 0.061 / 0.121. The error grows with the face's
  // distance from the template (face 9: 0.056 / 0.094).
  CHECK(classic_all.median() <= 0.05);
  CHECK(classic_all.p90() <= 0.08);
  CHECK(facerig::Percentile(classic_all.leaks, 0.5) <= 0.01);
  // Measured against each other: on same-topology ICT faces classic is the more accurate.
  CHECK(classic_all.median() < identity_all.median());
  CHECK(identity_all.median() <= 0.06);  // measured 0.051
}

TEST_CASE("eyeBlink closes the lids as far as the template's deltas do (shared data)",
          "[deformation_transfer][shared-data]") {
  const facerig::Rig& rig = facerig::test::IctRig();
  const std::vector<glm::vec3> face = RandomIctFace(11);
  const Meshes truth = TrueExpressions(face);
  const facerig::DeformationTransferResult classic =
      facerig::DeformationTransfer(facerig::NeutralMesh(rig), face, Ict().expressions);
  for (const char* name : {"eyeBlink_L", "eyeBlink_R"}) {
    const std::size_t s = *rig.FindShape(name);
    const facerig::OpeningMargins margins =
        facerig::FindEyelidMargins(facerig::NeutralMesh(rig), Ict().expressions[s], 0, ict::kBeforeTeeth.end);
    REQUIRE(margins.upper.size() >= 3);
    const facerig::OpeningGap on_template = facerig::MeasureOpeningGap(Ict().expressions[s], margins);
    const facerig::OpeningGap on_truth = facerig::MeasureOpeningGap(truth[s], margins);
    const facerig::OpeningGap transferred = facerig::MeasureOpeningGap(classic.expressions[s], margins);
    WARN(name << ", " << on_template.measured_vertices << " upper lid vertices on a " << margins.lower_margin.size()
              << "-vertex lower margin, gap / eye width mean, max, crossing: template " << on_template.mean_gap
              << ", " << on_template.max_gap << ", " << on_template.max_crossing << "; template deltas on the face "
              << on_truth.mean_gap << ", " << on_truth.max_gap << ", " << on_truth.max_crossing << "; transferred "
              << transferred.mean_gap << ", " << transferred.max_gap << ", " << transferred.max_crossing);
    REQUIRE(on_template.measured_vertices >= 3);
    // Open, the lids are far apart: the measure tells open from closed.
    CHECK(facerig::MeasureOpeningGap(rig.positions(), margins).mean_gap > 10.0 * on_template.mean_gap);
    // ICT's own blink leaves its margins 0.021 of the eye width apart (0.5-1.5 mm
    // medially, over the upper lid's margin row): issue 6's 1% is out of reach
    // of a faithful transfer, so the transfer is held to the template and the
    // template deltas instead.
    CHECK(on_template.mean_gap < 0.025);
    CHECK(transferred.mean_gap <= std::max(on_template.mean_gap, on_truth.mean_gap) + 0.01);
    CHECK(transferred.max_crossing <= std::max(on_template.max_crossing, on_truth.max_crossing) + 0.01);
  }
}
