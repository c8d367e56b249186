// The fitted template's lid margins onto the target's rims
// (openings.h), on sheets with a slit: the template's
// slit closes in its one expression; the target's slit is the same hole with
// its rims moved.
#include "facerig/offline/openings/margins.h"

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <optional>
#include <vector>

#include "facerig/runtime/rig_builder.h"
#include "support/slit_sheet.h"

namespace {

using facerig::test::SlitSheet;
using namespace facerig::test::slit;

// The slit sheet with its rows at row_y[y]; with_slit false: no hole.
facerig::RawRig MakeSheet(const std::vector<float>& row_y, bool with_slit) {
  SlitSheet grid = facerig::test::MakeSlitSheet(with_slit, row_y);
  facerig::RawRig sheet;
  sheet.positions = std::move(grid.positions);
  sheet.triangles = std::move(grid.triangles);
  return sheet;
}

const std::vector<float> kEvenRows = {0, 1, 2, 3, 4, 5, 6};

// The template: the slit's upper edge comes down onto the lower one (a blink).
facerig::Rig MakeTemplate() {
  facerig::RawRig sheet = MakeSheet(kEvenRows, true);
  sheet.shapes.push_back(facerig::MakeSparseShape("blink", facerig::test::SlitBlinkDeltas(), {}, 1e-6f));
  std::optional<facerig::Rig> rig = facerig::RigBuilder::Build(sheet);
  REQUIRE(rig.has_value());
  return std::move(*rig);
}

}  // namespace

TEST_CASE("Margin alignment: the template's closing slit is its margins", "[margin_alignment]") {
  const facerig::Rig rig = MakeTemplate();
  const std::vector<facerig::OpeningMargin> margins = facerig::FindOpeningMargins(rig);
  // The upper edge's moving vertices and the lower edge's below them, each
  // with the other as partner.
  REQUIRE(margins.size() == 2 * (kSlitLast - kSlitFirst - 1));
  for (const facerig::OpeningMargin& margin : margins) {
    const std::uint32_t x = margin.vertex % kColumns;
    const std::uint32_t y = margin.vertex / kColumns;
    CHECK(x > kSlitFirst);
    CHECK(x < kSlitLast);
    CHECK(margin.partner == Vertex(x, y == kSlitRow ? kSlitRow + 1 : kSlitRow));
  }
}

TEST_CASE("Margin alignment: margins go onto the target's rims, the sheet follows and fades",
          "[margin_alignment]") {
  const facerig::Rig rig = MakeTemplate();
  const std::vector<facerig::OpeningMargin> margins = facerig::FindOpeningMargins(rig);
  std::vector<glm::vec3> fitted(rig.positions().begin(), rig.positions().end());
  // The target's slit is narrower: its lower rim 0.2 higher, its upper 0.1 lower.
  const facerig::RawRig target = MakeSheet({0, 1, 2, 3.2f, 3.9f, 5, 6}, true);
  facerig::OpeningParams params;
  params.margin_reach = 1.5f;  // openings (here 1): the rows next to the slit's, not the ones beyond
  const facerig::MarginAlignmentResult result = facerig::AlignMarginsToOpenings(
      fitted, rig.triangles(), margins, target.positions, target.triangles, params);
  CHECK(result.aligned_vertices == margins.size());
  CHECK(result.max_correction == Approx(0.2).margin(1e-5));
  for (const facerig::OpeningMargin& margin : margins) {
    // Onto the rim straight below or above.
    CHECK(glm::length(fitted[margin.vertex] - target.positions[margin.vertex]) < 1e-5f);
  }
  // Outside the margins: the next rows move part of the way, in the same
  // direction; 1.5 openings away along the edges, nothing moves.
  const glm::vec3 above = fitted[Vertex(5, kSlitRow + 2)] - rig.positions()[Vertex(5, kSlitRow + 2)];
  CHECK(above.y < 0.0f);
  CHECK(above.y > -0.1f);
  const glm::vec3 below = fitted[Vertex(5, kSlitRow - 1)] - rig.positions()[Vertex(5, kSlitRow - 1)];
  CHECK(below.y > 0.0f);
  CHECK(below.y < 0.2f);
  for (std::uint32_t x = 0; x < kColumns; ++x) {
    for (std::uint32_t y : {0u, 1u, kRows - 1}) CHECK(fitted[Vertex(x, y)] == rig.positions()[Vertex(x, y)]);
  }
}

TEST_CASE("Margin alignment: no rim of a like opening, nothing moves", "[margin_alignment]") {
  const facerig::Rig rig = MakeTemplate();
  const std::vector<facerig::OpeningMargin> margins = facerig::FindOpeningMargins(rig);
  SECTION("the target has no hole there") {
    const facerig::RawRig target = MakeSheet(kEvenRows, false);
    std::vector<glm::vec3> fitted(rig.positions().begin(), rig.positions().end());
    const auto result =
        facerig::AlignMarginsToOpenings(fitted, rig.triangles(), margins, target.positions, target.triangles);
    CHECK(result.aligned_vertices == 0);
    CHECK(std::equal(fitted.begin(), fitted.end(), rig.positions().begin()));
  }
  SECTION("the target's slit is a tenth as wide (lips that touch, not an open eye)") {
    const facerig::RawRig target = MakeSheet({0, 1, 2, 3.45f, 3.55f, 5, 6}, true);
    std::vector<glm::vec3> fitted(rig.positions().begin(), rig.positions().end());
    const auto result =
        facerig::AlignMarginsToOpenings(fitted, rig.triangles(), margins, target.positions, target.triangles);
    CHECK(result.aligned_vertices == 0);
    CHECK(std::equal(fitted.begin(), fitted.end(), rig.positions().begin()));
  }
}
