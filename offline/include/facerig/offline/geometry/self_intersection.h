// Self-intersections of a triangle mesh: pairs of triangles that share no
// vertex and pass through each other: a transferred expression should create
// no self-intersection that the template's does not have.
//
// A pair counts when the two triangles cross: each has vertices strictly on
// both sides of the other's plane and their cuts along the planes' common line
// overlap over a positive length (Guigue & Devillers 2003, with exact
// orientation signs, so the answer does not depend on rounding). Hence:
// - triangles that only touch (a vertex or an edge resting on the other
//   triangle, one triangle entirely on one side) do not count;
// - pairs sharing a vertex index (neighbours along an edge or at a corner) are
//   never tested;
// - degenerate triangles (collinear or repeated vertices) have no plane and
//   never count (they are reported in degenerate_triangles);
// - coplanar overlaps (only made by construction, e.g. flat meshes) do not count.
//
// Broad phase: a uniform grid over the triangles' bounding boxes; each
// candidate pair is tested once. One thread (timings: docs/benchmarks.md,
// "Measurements behind the defaults").
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"

namespace facerig {

struct SelfIntersectionParams {
  // Only triangles whose three vertices all lie in [region_first, region_last)
  // are tested (against each other). Default: the whole mesh.
  std::size_t region_first = 0;
  std::size_t region_last = std::numeric_limits<std::size_t>::max();
  // Keep up to this many intersecting pairs in the result (the count is always complete).
  std::size_t max_pairs = 0;
};

struct SelfIntersectionResult {
  std::size_t intersecting_pairs = 0;
  // (first, second) triangle indices, first < second, sorted; at most params.max_pairs.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  std::size_t tested_triangles = 0;      // triangles in the region
  std::size_t degenerate_triangles = 0;  // of those, with no plane
  std::size_t candidate_pairs = 0;       // bounding boxes overlapping, no shared vertex
  double seconds = 0.0;
};

// \pre every triangle index < positions.size(); positions finite.
// \throw InvalidInputError for an out-of-range triangle index or a non-finite position.
SelfIntersectionResult FindSelfIntersections(const Mesh& mesh, const SelfIntersectionParams& params = {});

// True when the two triangles cross (the pair rule above; shared vertices are
// not looked at here: pass triangles of distinct vertices).
bool TrianglesCross(const glm::vec3& p1, const glm::vec3& q1, const glm::vec3& r1, const glm::vec3& p2,
                    const glm::vec3& q2, const glm::vec3& r2);

// How deeply two crossing triangles pass through each other, so that a count
// of crossing pairs (inflated where triangles are small, as in a lip corner's
// crease) can be told from a visible one: for each triangle, the shorter of
// the distances its vertices reach on the two sides of the other's plane; the
// smaller of the two. 0 when a triangle stays on one side or either is
// degenerate. Two triangles cut through each other by d give d.
float CrossingDepth(const glm::vec3& p1, const glm::vec3& q1, const glm::vec3& r1, const glm::vec3& p2,
                    const glm::vec3& q2, const glm::vec3& r2);

// Exact sign (-1, 0, +1) of det[a - d; b - d; c - d] for float inputs: a
// floating-point filter, then an exact expansion sum of the determinant's 24
// monomials when the filter cannot decide. Positive when d is below the plane
// through a, b, c seen counter-clockwise from above (Shewchuk's orient3d).
int Orient3dSign(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d);

}  // namespace facerig
