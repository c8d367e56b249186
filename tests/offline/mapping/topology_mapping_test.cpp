// Blend shapes onto the target's own vertices (topology_mapping.h): rim
// vertices of an opening take the motion of the template's margin on their
// side, not of a point inside their lid.
#include "facerig/offline/mapping/topology_mapping.h"

#include "facerig/offline/error.h"
#include "facerig/runtime/rig_builder.h"
#include "support/slit_sheet.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <utility>
#include <glm/geometric.hpp>
#include <vector>

namespace {

using facerig::test::SlitSheet;
using namespace facerig::test::slit;

// The slit's edges as template rims, each towards the other edge; flipped:
// the wrong way.
std::vector<facerig::MarginDirection> SlitRims(bool flipped) {
  std::vector<facerig::MarginDirection> rims;
  const float sign = flipped ? -1.0f : 1.0f;
  for (std::uint32_t x = kSlitFirst + 1; x < kSlitLast; ++x) rims.push_back({Vertex(x, kSlitRow), {0, sign, 0}});
  for (std::uint32_t x = kSlitFirst + 1; x < kSlitLast; ++x) rims.push_back({Vertex(x, kSlitRow + 1), {0, -sign, 0}});
  return rims;
}

std::vector<glm::vec3> MappedBlink(const SlitSheet& sheet, std::span<const facerig::MarginDirection> rims,
                                   std::size_t* rim_vertices) {
  facerig::TopologyMappingParams params;
  const facerig::TopologyMapping mapping = facerig::ComputeTopologyMapping(sheet, sheet, params, rims);
  *rim_vertices = mapping.rim_vertices;
  std::vector<glm::vec3> mapped;
  facerig::MapVertexValues(mapping, sheet.triangles, facerig::test::SlitBlinkDeltas(), mapped);
  return mapped;
}

}  // namespace

TEST_CASE("Topology mapping: rim vertices take their own margin's motion", "[topology_mapping]") {
  const SlitSheet sheet = facerig::test::MakeSlitSheet();  // the target is the template's own sheet
  const std::vector<glm::vec3> template_deltas = facerig::test::SlitBlinkDeltas();
  std::size_t rim_vertices = 0;

  // Without rims, a rim vertex looks from slightly inside its lid
  // (boundary_inset) and moves less than the margin.
  const std::vector<glm::vec3> plain = MappedBlink(sheet, {}, &rim_vertices);
  CHECK(rim_vertices == 0);
  const glm::vec3 upper_rim = plain[Vertex(5, kSlitRow + 1)];
  CHECK(upper_rim.y > -0.97f);

  // With them, every rim vertex along the margins moves exactly as its margin.
  const std::vector<facerig::MarginDirection> rims = SlitRims(false);
  const std::vector<glm::vec3> snapped = MappedBlink(sheet, rims, &rim_vertices);
  CHECK(rim_vertices == rims.size());
  for (const facerig::MarginDirection& rim : rims) {
    CHECK(glm::length(snapped[rim.vertex] - template_deltas[rim.vertex]) < 1e-5f);
  }

  // Rims that open the other way are not the target rims' side: as without.
  const std::vector<facerig::MarginDirection> flipped = SlitRims(true);
  const std::vector<glm::vec3> wrong_way = MappedBlink(sheet, flipped, &rim_vertices);
  CHECK(rim_vertices == 0);
  CHECK(glm::length(wrong_way[Vertex(5, kSlitRow + 1)] - upper_rim) < 1e-6f);
}

TEST_CASE("Topology mapping: where the template's margin ends early, the rim is smoothed, not stepped",
          "[topology_mapping]") {
  const SlitSheet sheet = facerig::test::MakeSlitSheet();
  // A smooth blink: the slit's upper edge down by up to 0.98, a sine along x
  // that is 0 at the slit's ends, the row above by half.
  std::vector<glm::vec3> blink(kColumns * kRows, glm::vec3(0.0f));
  for (std::uint32_t x = kSlitFirst; x <= kSlitLast; ++x) {
    const float along = std::sin(3.14159265f * static_cast<float>(x - kSlitFirst) / (kSlitLast - kSlitFirst));
    blink[Vertex(x, kSlitRow + 1)].y = -0.98f * along;
    blink[Vertex(x, kSlitRow + 2)].y = -0.49f * along;
  }
  // Only the right part of the upper margin (x = 5..7) is a template rim, as
  // when the template's margin ends before the target's rim: x = 3, 4 take a
  // point inside the lid (a deep inset here, so that it shows) and lag.
  std::vector<facerig::MarginDirection> rims;
  for (std::uint32_t x = 5; x < kSlitLast; ++x) rims.push_back({Vertex(x, kSlitRow + 1), {0, -1, 0}});
  const auto mapped_with = [&](float radius, int expected_passes) {
    facerig::TopologyMappingParams params;
    params.openings.boundary_inset = 0.03f;
    params.openings.rim_smoothing_radius = radius;
    const facerig::TopologyMapping mapping = facerig::ComputeTopologyMapping(sheet, sheet, params, rims);
    CHECK(mapping.rim_vertices == 3);
    REQUIRE(mapping.rims.size() == 1);
    CHECK(mapping.rims[0].passes == expected_passes);
    std::vector<glm::vec3> mapped;
    facerig::MapVertexValues(mapping, sheet.triangles, blink, mapped);
    return mapped;
  };
  // The jump where snapping starts, beyond the template's own there.
  const auto extra_step = [&](const std::vector<glm::vec3>& mapped) {
    const std::uint32_t a = Vertex(4, kSlitRow + 1), b = Vertex(5, kSlitRow + 1);
    return glm::length((mapped[b] - mapped[a]) - (blink[b] - blink[a]));
  };
  const std::vector<glm::vec3> stepped = mapped_with(0.0f, 0);
  // The default radius is far below this coarse sheet's vertex spacing: left as it is.
  CHECK(mapped_with(facerig::OpeningParams{}.rim_smoothing_radius, 0) == stepped);
  // About one vertex spacing (the sheet's diagonal is 11.7 spacings): 2 passes.
  const std::vector<glm::vec3> smoothed = mapped_with(1.0f / 11.7f, 2);
  WARN("extra step where the rim starts snapping: " << extra_step(stepped) << " unsmoothed, " << extra_step(smoothed)
                                                    << " smoothed");
  CHECK(extra_step(stepped) > 0.1f);
  CHECK(extra_step(smoothed) < 0.3f * extra_step(stepped));
  // The lower rim, which faces the other way, takes none of the upper's motion.
  for (std::uint32_t x = kSlitFirst + 1; x < kSlitLast; ++x) {
    INFO("x " << x);
    CHECK(smoothed[Vertex(x, kSlitRow)] == stepped[Vertex(x, kSlitRow)]);
  }
  // Away from the rim nothing changes.
  for (std::uint32_t v = 0; v < kColumns * kRows; ++v) {
    if (v / kColumns == kSlitRow || v / kColumns == kSlitRow + 1) continue;
    CHECK(smoothed[v] == stepped[v]);
  }
  for (float bad : {-0.1f, std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()}) {
    facerig::TopologyMappingParams params;
    params.openings.rim_smoothing_radius = bad;
    CHECK_THROWS_AS(facerig::ComputeTopologyMapping(sheet, sheet, params, rims),
                    facerig::InvalidInputError);
  }
}

TEST_CASE("Topology mapping: a rim whose sides an expression brings together closes, or stops crossing",
          "[topology_mapping]") {
  const SlitSheet sheet = facerig::test::MakeSlitSheet();
  const std::vector<facerig::MarginDirection> rims = SlitRims(false);
  const facerig::TopologyMapping mapping =
      facerig::ComputeTopologyMapping(sheet, sheet, {}, rims);
  REQUIRE(mapping.rims.size() == 1);
  CHECK(mapping.rims[0].rest_gap[0] > 0.0f);
  // The slit's upper edge comes down by `drop` of its 1.0 gap, the row above by half.
  const auto closed_with = [&](float drop) {
    std::vector<glm::vec3> blink(kColumns * kRows, glm::vec3(0.0f));
    for (std::uint32_t x = kSlitFirst + 1; x < kSlitLast; ++x) {
      blink[Vertex(x, kSlitRow + 1)].y = -drop;
      blink[Vertex(x, kSlitRow + 2)].y = -0.5f * drop;
    }
    std::vector<glm::vec3> deltas;
    facerig::MapVertexValues(mapping, sheet.triangles, blink, deltas);
    std::vector<glm::vec3> before = deltas;
    facerig::CloseRims(mapping, sheet.positions, deltas);
    return std::pair{before, deltas};
  };
  // The largest gap between the slit's sides, upper minus lower height.
  const auto widest = [&](const std::vector<glm::vec3>& deltas) {
    float largest = 0.0f;
    for (std::uint32_t x = kSlitFirst + 1; x < kSlitLast; ++x) {
      const std::uint32_t upper = Vertex(x, kSlitRow + 1), lower = Vertex(x, kSlitRow);
      const float gap = sheet.positions[upper].y + deltas[upper].y - sheet.positions[lower].y - deltas[lower].y;
      if (std::abs(gap) > std::abs(largest)) largest = gap;
    }
    return largest;
  };
  // Nearly closed (10% open): closed, each side moving half.
  const auto [open10, closed10] = closed_with(0.9f);
  CHECK(std::abs(widest(open10) - 0.1f) < 1e-4f);
  CHECK(std::abs(widest(closed10)) < 1e-3f);
  CHECK(closed10[Vertex(5, kSlitRow)].y == Approx(0.05f).margin(1e-3));
  // Crossing by 0.1: back to meeting, but for the vertices next to the slit's
  // ends, whose nearest point on the other side lies on the sloping end edge.
  const auto [crossed, uncrossed] = closed_with(1.1f);
  CHECK(widest(crossed) < -0.09f);
  CHECK(std::abs(widest(uncrossed)) < 0.03f);
  for (std::uint32_t x = kSlitFirst + 2; x + 1 < kSlitLast; ++x) {
    const float gap = sheet.positions[Vertex(x, kSlitRow + 1)].y + uncrossed[Vertex(x, kSlitRow + 1)].y -
                      sheet.positions[Vertex(x, kSlitRow)].y - uncrossed[Vertex(x, kSlitRow)].y;
    CHECK(std::abs(gap) < 1e-3f);
  }
  // Half closed (a squint): left as it is.
  const auto [half, half_after] = closed_with(0.5f);
  CHECK(half_after == half);
  // The rows away from the rim do not move (the lid follows only within half the gap).
  for (std::uint32_t x = 0; x < kColumns; ++x) CHECK(closed10[Vertex(x, 0)] == open10[Vertex(x, 0)]);
  // Off: nothing closes.
  facerig::TopologyMappingParams off;
  off.openings.rim_closing_ratio = 0.0f;
  const facerig::TopologyMapping plain =
      facerig::ComputeTopologyMapping(sheet, sheet, off, rims);
  std::vector<glm::vec3> deltas = open10;
  facerig::CloseRims(plain, sheet.positions, deltas);
  CHECK(deltas == open10);
  for (float bad : {-0.1f, 1.0f, std::numeric_limits<float>::quiet_NaN()}) {
    facerig::TopologyMappingParams params;
    params.openings.rim_closing_ratio = bad;
    CHECK_THROWS_AS(facerig::ComputeTopologyMapping(sheet, sheet, params, rims),
                    facerig::InvalidInputError);
  }
  for (float bad : {0.0f, -1.0f, std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()}) {
    facerig::TopologyMappingParams params;
    params.openings.rim_closing_reach = bad;
    CHECK_THROWS_AS(facerig::ComputeTopologyMapping(sheet, sheet, params, rims),
                    facerig::InvalidInputError);
  }
}

TEST_CASE("Topology mapping: template rims out of range or out of order are refused", "[topology_mapping]") {
  const SlitSheet sheet = facerig::test::MakeSlitSheet();
  const std::vector<facerig::MarginDirection> out_of_range = {{kColumns * kRows, {0, 1, 0}}};
  CHECK_THROWS_WITH(facerig::ComputeTopologyMapping(sheet, sheet, {}, out_of_range),
                    Catch::Contains("template rim vertex 77"));
  const std::vector<facerig::MarginDirection> unordered = {{Vertex(4, 4), {0, -1, 0}}, {Vertex(3, 4), {0, -1, 0}}};
  CHECK_THROWS_WITH(facerig::ComputeTopologyMapping(sheet, sheet, {}, unordered),
                    Catch::Contains("out of order"));
}

namespace {

facerig::RawBlendShape ShapeOnAll(const std::string& name, std::size_t vertex_count, glm::vec3 delta) {
  facerig::RawBlendShape shape{name, {}, {}, {}};
  for (std::uint32_t v = 0; v < vertex_count; ++v) {
    shape.vertex_indices.push_back(v);
    shape.position_deltas.push_back(delta);
  }
  return shape;
}

}  // namespace

TEST_CASE("Topology mapping: template shapes replace the target's own of the same meaning, in any spelling",
          "[topology_mapping]") {
  const SlitSheet sheet = facerig::test::MakeSlitSheet();
  const std::size_t n = sheet.positions.size();
  facerig::RawRig template_raw;
  template_raw.positions = sheet.positions;
  template_raw.triangles = sheet.triangles;
  template_raw.shapes = {ShapeOnAll("eyeBlink_L", n, {0, 1, 0}), ShapeOnAll("browInnerUp_R", n, {0, 2, 0})};
  const std::optional<facerig::Rig> template_rig = facerig::RigBuilder::Build(template_raw);
  REQUIRE(template_rig);
  facerig::RawRig target;
  target.positions = sheet.positions;
  target.triangles = sheet.triangles;
  // ARKit spellings of the template's shapes, an unsided one the template
  // has a side of, and two the template lacks.
  target.shapes = {ShapeOnAll("eyeBlinkLeft", n, {0, 0, 1}), ShapeOnAll("browInnerUp", n, {0, 0, 2}),
                   ShapeOnAll("eyeBlinkRight", n, {0, 0, 3}), ShapeOnAll("viseme_aa", n, {0, 0, 4})};
  const facerig::TopologyMapping mapping = facerig::ComputeTopologyMapping(sheet, sheet, {}, {});
  const facerig::RawRig mapped = facerig::MapRigToTarget(*template_rig, mapping, target);
  std::vector<std::string> names;
  for (const facerig::RawBlendShape& shape : mapped.shapes) names.push_back(shape.name);
  CHECK(names == std::vector<std::string>{"eyeBlink_L", "browInnerUp_R", "eyeBlinkRight", "viseme_aa"});
}

namespace {

// A flat sheet of two quads, one above the other (rows y = -1, 0, 1),
// triangles 0-1 below, 2-3 above; shifted by `offset`.
facerig::Mesh TwoQuadSheet(glm::vec3 offset) {
  facerig::Mesh sheet;
  for (float y : {-1.0f, 0.0f, 1.0f}) {
    for (float x : {0.0f, 1.0f}) sheet.positions.push_back(glm::vec3(x, y, 0.0f) + offset);
  }
  sheet.triangles = {{0, 1, 3}, {0, 3, 2}, {2, 3, 5}, {2, 5, 4}};
  return sheet;
}

}  // namespace

TEST_CASE("Topology mapping: a vertex on one side of the mouth searches only the template's same side",
          "[topology_mapping]") {
  using facerig::MouthSide;
  const facerig::Mesh fitted_template = TwoQuadSheet(glm::vec3(0.0f));
  // The target's middle row lies just below the template's: nearest to its lower quad.
  const facerig::Mesh target = TwoQuadSheet(glm::vec3(0.0f, -0.1f, 0.01f));
  facerig::MouthSides sides;
  sides.template_triangle = {MouthSide::kLower, MouthSide::kLower, MouthSide::kUpper, MouthSide::kUpper};
  sides.target_vertex = {MouthSide::kLower, MouthSide::kLower, MouthSide::kUpper,
                         MouthSide::kUpper, MouthSide::kUpper, MouthSide::kUpper};
  const facerig::TopologyMapping plain = facerig::ComputeTopologyMapping(fitted_template, target);
  const facerig::TopologyMapping sided = facerig::ComputeTopologyMapping(fitted_template, target, {}, {}, sides);
  for (std::uint32_t v : {2u, 3u}) {
    INFO("target vertex " << v);
    CHECK(plain.triangle[v] < 2);   // the lower quad, nearest
    CHECK(sided.triangle[v] >= 2);  // the upper quad, its own side
  }
  CHECK(sided.triangle[0] < 2);
  sides.target_vertex.pop_back();
  CHECK_THROWS_WITH(facerig::ComputeTopologyMapping(fitted_template, target, {}, {}, sides),
                    Catch::Contains("mouth sides"));
}
