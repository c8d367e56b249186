// The eyelid measure on a synthetic eye: two strips, a lower lid (margin row
// y = 0) and an upper lid (margin row y = 1), with no triangle across the gap.
#include <catch2/catch.hpp>
#include <cstdint>
#include <utility>
#include <vector>

#include "facerig/offline/openings/gaps.h"

#include "facerig/offline/error.h"
#include "support/test_meshes.h"

namespace {

constexpr std::uint32_t kEyeColumns = 5;  // x = 0..4
// Rows of kEyeColumns vertices: lower margin, skin below it, upper margin, skin above it.
constexpr std::uint32_t kLowerMargin = 0;
constexpr std::uint32_t kBelow = 1;
constexpr std::uint32_t kUpperMargin = 2;
constexpr std::uint32_t kAbove = 3;

std::uint32_t EyeVertex(std::uint32_t row, std::uint32_t column) { return row * kEyeColumns + column; }

std::vector<glm::vec3> OpenEye() {
  std::vector<glm::vec3> positions;
  for (const float y : {0.0f, -1.0f, 1.0f, 2.0f}) {
    for (std::uint32_t x = 0; x < kEyeColumns; ++x) positions.emplace_back(static_cast<float>(x), y, 0.0f);
  }
  return positions;
}

std::vector<facerig::Triangle> EyeTriangles() {
  std::vector<facerig::Triangle> triangles;
  for (const auto& [margin, skin] : {std::pair{kLowerMargin, kBelow}, std::pair{kUpperMargin, kAbove}}) {
    for (std::uint32_t x = 0; x + 1 < kEyeColumns; ++x) {
      triangles.push_back({EyeVertex(margin, x), EyeVertex(skin, x), EyeVertex(skin, x + 1)});
      triangles.push_back({EyeVertex(margin, x), EyeVertex(skin, x + 1), EyeVertex(margin, x + 1)});
    }
  }
  return triangles;
}

// The upper margin at height y, each vertex slid along x as given.
std::vector<glm::vec3> UpperMarginAt(float y, const std::vector<float>& slide) {
  std::vector<glm::vec3> positions = OpenEye();
  for (std::uint32_t x = 0; x < kEyeColumns; ++x) {
    positions[EyeVertex(kUpperMargin, x)] = {static_cast<float>(x) + slide[x], y, 0.0f};
  }
  return positions;
}

}  // namespace

TEST_CASE("Eyelid gap: the lids meet as curves though the lid slides", "[deformation_transfer]") {
  // Blink: the upper margin comes down onto the lower one, sliding. Columns 1
  // and 3 land halfway between lower vertices, too far from any to pair.
  const std::vector<float> slide{0.05f, 0.5f, 0.05f, 0.5f, -0.05f};
  const std::vector<glm::vec3> neutral = OpenEye();
  const std::vector<glm::vec3> blink = UpperMarginAt(0.0f, slide);
  const facerig::OpeningMargins margins =
      facerig::FindEyelidMargins(facerig::test::MeshOf(neutral, EyeTriangles()), blink, 0, neutral.size());
  CHECK(margins.upper == std::vector<std::uint32_t>{EyeVertex(kUpperMargin, 0), EyeVertex(kUpperMargin, 2),
                                                    EyeVertex(kUpperMargin, 4)});
  CHECK(margins.lower == std::vector<std::uint32_t>{EyeVertex(kLowerMargin, 0), EyeVertex(kLowerMargin, 2),
                                                    EyeVertex(kLowerMargin, 4)});
  // The whole lower margin row, not only the partners.
  CHECK(margins.lower_margin == std::vector<std::uint32_t>{0, 1, 2, 3, 4});
  CHECK(margins.width == Approx(4.0));

  // Paired vertex to vertex the closed eye would be 0.05 / 4 apart; on the curve, 0.
  const facerig::OpeningGap closed = facerig::MeasureOpeningGap(blink, margins);
  CHECK(closed.measured_vertices == 3);
  CHECK(closed.mean_gap == Approx(0.0).margin(1e-7));
  CHECK(closed.max_gap == Approx(0.0).margin(1e-7));
  CHECK(closed.max_crossing == Approx(0.0).margin(1e-7));

  const facerig::OpeningGap ajar = facerig::MeasureOpeningGap(UpperMarginAt(0.2f, slide), margins);
  CHECK(ajar.mean_gap == Approx(0.05));
  CHECK(ajar.max_gap == Approx(0.05));
  CHECK(ajar.max_crossing == 0.0);
  CHECK(facerig::MeasureOpeningGap(neutral, margins).mean_gap == Approx(0.25));

  // Through the lower lid: as far below as apart, and counted as crossing.
  const facerig::OpeningGap crossed = facerig::MeasureOpeningGap(UpperMarginAt(-0.1f, slide), margins);
  CHECK(crossed.mean_gap == Approx(0.025));
  CHECK(crossed.max_crossing == Approx(0.025));

  // Past the end of the lower margin (the lid corner): not measured.
  const std::vector<float> past_corner{0.05f, 0.5f, 0.05f, 0.5f, 0.5f};
  const facerig::OpeningGap cornered = facerig::MeasureOpeningGap(UpperMarginAt(0.3f, past_corner), margins);
  CHECK(cornered.measured_vertices == 2);
  CHECK(cornered.mean_gap == Approx(0.075));
}

TEST_CASE("Eyelid margins: invalid inputs", "[deformation_transfer]") {
  const std::vector<glm::vec3> neutral = OpenEye();
  const std::vector<facerig::Triangle> triangles = EyeTriangles();
  const std::vector<glm::vec3> short_mesh{{0, 0, 0}};
  CHECK_THROWS_AS(facerig::FindEyelidMargins(facerig::test::MeshOf(neutral, triangles), short_mesh, 0, neutral.size()),
                  facerig::MeshInputError);
  // Nothing moves: no lids meet.
  CHECK_THROWS_AS(facerig::FindEyelidMargins(facerig::test::MeshOf(neutral, triangles), neutral, 0, neutral.size()),
                  facerig::MeshInputError);
  // The lids meet at one vertex only: no lower margin to measure along.
  std::vector<glm::vec3> pinch = neutral;
  pinch[EyeVertex(kUpperMargin, 2)].y = 0.0f;
  CHECK_THROWS_AS(facerig::FindEyelidMargins(facerig::test::MeshOf(neutral, triangles), pinch, 0, neutral.size()),
                  facerig::MeshInputError);
  // The lower margin's vertices are joined by no edge.
  const std::vector<glm::vec3> blink = UpperMarginAt(0.0f, {0.0f, 0.0f, 0.0f, 0.0f, 0.0f});
  CHECK_THROWS_AS(facerig::FindEyelidMargins(facerig::test::MeshOf(neutral, {}), blink, 0, neutral.size()), facerig::MeshInputError);
}
