#include "facerig/offline/geometry/self_intersection.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <stdexcept>
#include <string>
#include <vector>
#include "facerig/offline/geometry/stats.h"
#include "facerig/offline/error.h"

namespace facerig {
namespace {

// --- Exact arithmetic (Shewchuk 1997): nonoverlapping expansions of doubles ---

// a + b = sum + error exactly.
inline void TwoSum(double a, double b, double& sum, double& error) {
  sum = a + b;
  const double b_virtual = sum - a;
  const double a_virtual = sum - b_virtual;
  error = (a - a_virtual) + (b - b_virtual);
}

// An exact sum of doubles, kept as a nonoverlapping expansion with zeros
// eliminated (grow_expansion_zeroelim); its sign is the sign of its largest
// component. Capacity: one component per term added.
template <std::size_t kCapacity>
class Expansion {
 public:
  void Add(double b) {
    double q = b;
    std::size_t out = 0;
    for (std::size_t i = 0; i < size_; ++i) {
      double sum = 0.0;
      double error = 0.0;
      TwoSum(q, components_[i], sum, error);
      q = sum;
      if (error != 0.0) components_[out++] = error;
    }
    if (q != 0.0 || out == 0) components_[out++] = q;
    size_ = out;
  }
  // a * b, exactly (FMA gives the rounding error of the product).
  void AddProduct(double a, double b) {
    const double product = a * b;
    Add(std::fma(a, b, -product));
    Add(product);
  }
  int Sign() const {
    if (size_ == 0) return 0;
    const double top = components_[size_ - 1];
    return (top > 0.0) - (top < 0.0);
  }

 private:
  std::array<double, kCapacity> components_{};
  std::size_t size_ = 0;
};

// det of the 4x4 matrix with rows (x, y, z, 1) for a, b, c, d, exactly: 24
// monomials x_i y_j z_k (i, j, k distinct rows), each the product of three
// floats; x_i y_j is exact in double (2 x 24 bits), times z_k is a 2-term
// expansion. No overflow or underflow is possible for finite floats.
int ExactOrient3dSign(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d) {
  const std::array<const glm::vec3*, 4> rows = {&a, &b, &c, &d};
  std::array<int, 4> column_of_row = {0, 1, 2, 3};
  Expansion<56> sum;
  do {
    int inversions = 0;
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) inversions += column_of_row[i] > column_of_row[j];
    }
    std::array<double, 3> factor{};  // x, y, z of the rows given columns 0, 1, 2
    for (int r = 0; r < 4; ++r) {
      if (column_of_row[r] < 3) factor[column_of_row[r]] = static_cast<double>((*rows[r])[column_of_row[r]]);
    }
    const double xy = factor[0] * factor[1];  // exact
    const double z = (inversions % 2 == 0) ? factor[2] : -factor[2];
    sum.AddProduct(xy, z);
  } while (std::next_permutation(column_of_row.begin(), column_of_row.end()));
  return sum.Sign();
}

// Exact sign of the 2D orientation of (a, b, c) in the plane of coordinates u, v.
int ExactOrient2dSign(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, int u, int v) {
  // det [[a_u a_v 1] [b_u b_v 1] [c_u c_v 1]]: six products of two floats, each exact.
  Expansion<8> sum;
  auto au = static_cast<double>(a[u]), av = static_cast<double>(a[v]);
  auto bu = static_cast<double>(b[u]), bv = static_cast<double>(b[v]);
  auto cu = static_cast<double>(c[u]), cv = static_cast<double>(c[v]);
  sum.Add(au * bv);
  sum.Add(-au * cv);
  sum.Add(bu * cv);
  sum.Add(-bu * av);
  sum.Add(cu * av);
  sum.Add(-cu * bv);
  return sum.Sign();
}

// No plane: the three vertices are collinear (or repeated).
bool IsDegenerate(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  return ExactOrient2dSign(a, b, c, 0, 1) == 0 && ExactOrient2dSign(a, b, c, 1, 2) == 0 &&
         ExactOrient2dSign(a, b, c, 2, 0) == 0;
}

// Guigue & Devillers' interval check on the planes' common line, in canonical
// form (p1 alone on its side of plane 2, p2 alone on its side of plane 1):
// strict, so the cuts must overlap over a positive length.
bool CutsOverlap(const glm::vec3& p1, const glm::vec3& q1, const glm::vec3& r1, const glm::vec3& p2,
                 const glm::vec3& q2, const glm::vec3& r2) {
  return Orient3dSign(q2, p2, p1, q1) < 0 && Orient3dSign(r2, p2, r1, p1) < 0;
}

// Puts triangle 2 in canonical form given the signs of its vertices against plane 1.
bool CanonicalSecond(const glm::vec3& p1, const glm::vec3& q1, const glm::vec3& r1, const glm::vec3& p2,
                     const glm::vec3& q2, const glm::vec3& r2, int dp2, int dq2, int dr2) {
  if (dp2 > 0) {
    if (dq2 > 0) return CutsOverlap(p1, r1, q1, r2, p2, q2);
    if (dr2 > 0) return CutsOverlap(p1, r1, q1, q2, r2, p2);
    return CutsOverlap(p1, q1, r1, p2, q2, r2);
  }
  if (dp2 < 0) {
    if (dq2 < 0) return CutsOverlap(p1, q1, r1, r2, p2, q2);
    if (dr2 < 0) return CutsOverlap(p1, q1, r1, q2, r2, p2);
    return CutsOverlap(p1, r1, q1, p2, q2, r2);
  }
  if (dq2 < 0) {
    if (dr2 >= 0) return CutsOverlap(p1, r1, q1, q2, r2, p2);
    return CutsOverlap(p1, q1, r1, p2, q2, r2);
  }
  if (dq2 > 0) {
    if (dr2 > 0) return CutsOverlap(p1, r1, q1, p2, q2, r2);
    return CutsOverlap(p1, q1, r1, q2, r2, p2);
  }
  if (dr2 > 0) return CutsOverlap(p1, q1, r1, r2, p2, q2);
  if (dr2 < 0) return CutsOverlap(p1, r1, q1, r2, p2, q2);
  return false;  // coplanar: not counted
}

bool StraddlesStrictly(int a, int b, int c) { return (a > 0 || b > 0 || c > 0) && (a < 0 || b < 0 || c < 0); }

// --- Broad phase ---

struct Box {
  glm::vec3 lo;
  glm::vec3 hi;
};

struct Grid {
  glm::vec3 origin{0.0f};
  float inverse_cell = 1.0f;
  std::array<std::int64_t, 3> size{1, 1, 1};

  std::array<std::int64_t, 3> CellOf(const glm::vec3& p) const {
    std::array<std::int64_t, 3> cell{};
    for (int k = 0; k < 3; ++k) {
      const auto c = static_cast<std::int64_t>(std::floor((p[k] - origin[k]) * inverse_cell));
      cell[static_cast<std::size_t>(k)] = std::clamp<std::int64_t>(c, 0, size[static_cast<std::size_t>(k)] - 1);
    }
    return cell;
  }
  std::int64_t Index(const std::array<std::int64_t, 3>& c) const {
    return (c[2] * size[1] + c[1]) * size[0] + c[0];
  }
};

}  // namespace

int Orient3dSign(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d) {
  // Shewchuk's orient3d filter (errboundA) on the double values of the floats.
  const double adx = static_cast<double>(a.x) - d.x, ady = static_cast<double>(a.y) - d.y,
               adz = static_cast<double>(a.z) - d.z;
  const double bdx = static_cast<double>(b.x) - d.x, bdy = static_cast<double>(b.y) - d.y,
               bdz = static_cast<double>(b.z) - d.z;
  const double cdx = static_cast<double>(c.x) - d.x, cdy = static_cast<double>(c.y) - d.y,
               cdz = static_cast<double>(c.z) - d.z;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (std::abs(bdxcdy) + std::abs(cdxbdy)) * std::abs(adz) +
                           (std::abs(cdxady) + std::abs(adxcdy)) * std::abs(bdz) +
                           (std::abs(adxbdy) + std::abs(bdxady)) * std::abs(cdz);
  constexpr double kEpsilon = 1.1102230246251565e-16;  // 2^-53
  constexpr double kErrorBound = (7.0 + 56.0 * kEpsilon) * kEpsilon;
  const double bound = kErrorBound * permanent;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return ExactOrient3dSign(a, b, c, d);
}

bool TrianglesCross(const glm::vec3& p1, const glm::vec3& q1, const glm::vec3& r1, const glm::vec3& p2,
                    const glm::vec3& q2, const glm::vec3& r2) {
  // Sides of triangle 1's vertices against plane 2 (Guigue & Devillers' dp1 = det[p1 - r2; p2 - r2; q2 - r2]).
  const int dp1 = Orient3dSign(p1, p2, q2, r2);
  const int dq1 = Orient3dSign(q1, p2, q2, r2);
  const int dr1 = Orient3dSign(r1, p2, q2, r2);
  if (!StraddlesStrictly(dp1, dq1, dr1)) return false;
  const int dp2 = Orient3dSign(p2, p1, q1, r1);
  const int dq2 = Orient3dSign(q2, p1, q1, r1);
  const int dr2 = Orient3dSign(r2, p1, q1, r1);
  if (!StraddlesStrictly(dp2, dq2, dr2)) return false;
  // Canonical form of triangle 1 (p1 alone on its side), then of triangle 2.
  if (dp1 > 0) {
    if (dq1 > 0) return CanonicalSecond(r1, p1, q1, p2, r2, q2, dp2, dr2, dq2);
    if (dr1 > 0) return CanonicalSecond(q1, r1, p1, p2, r2, q2, dp2, dr2, dq2);
    return CanonicalSecond(p1, q1, r1, p2, q2, r2, dp2, dq2, dr2);
  }
  if (dp1 < 0) {
    if (dq1 < 0) return CanonicalSecond(r1, p1, q1, p2, q2, r2, dp2, dq2, dr2);
    if (dr1 < 0) return CanonicalSecond(q1, r1, p1, p2, q2, r2, dp2, dq2, dr2);
    return CanonicalSecond(p1, q1, r1, p2, r2, q2, dp2, dr2, dq2);
  }
  if (dq1 < 0) {
    if (dr1 >= 0) return CanonicalSecond(q1, r1, p1, p2, r2, q2, dp2, dr2, dq2);
    return CanonicalSecond(p1, q1, r1, p2, q2, r2, dp2, dq2, dr2);
  }
  if (dq1 > 0) {
    if (dr1 > 0) return CanonicalSecond(p1, q1, r1, p2, r2, q2, dp2, dr2, dq2);
    return CanonicalSecond(q1, r1, p1, p2, q2, r2, dp2, dq2, dr2);
  }
  if (dr1 > 0) return CanonicalSecond(r1, p1, q1, p2, q2, r2, dp2, dq2, dr2);
  return CanonicalSecond(r1, p1, q1, p2, r2, q2, dp2, dr2, dq2);
}

namespace {

// Triangles of the region with a plane (indices into `triangles`) and their boxes.
struct TestedTriangles {
  std::vector<std::uint32_t> index;
  std::vector<Box> boxes;
};

TestedTriangles CollectTestedTriangles(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                                       const SelfIntersectionParams& params, SelfIntersectionResult& result) {
  const std::size_t region_last = std::min(params.region_last, positions.size());
  auto in_region = [&](std::uint32_t v) { return v >= params.region_first && v < region_last; };
  TestedTriangles tested;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Triangle& tri = triangles[t];
    for (const std::uint32_t v : tri) {
      if (v >= positions.size()) {
        throw InvalidInputError("FindSelfIntersections: triangle " + std::to_string(t) + " uses vertex " +
                                    std::to_string(v) + " of " + std::to_string(positions.size()));
      }
    }
    if (!in_region(tri[0]) || !in_region(tri[1]) || !in_region(tri[2])) continue;
    const glm::vec3& a = positions[tri[0]];
    const glm::vec3& b = positions[tri[1]];
    const glm::vec3& c = positions[tri[2]];
    for (const glm::vec3* p : {&a, &b, &c}) {
      if (!std::isfinite(p->x) || !std::isfinite(p->y) || !std::isfinite(p->z)) {
        throw InvalidInputError("FindSelfIntersections: triangle " + std::to_string(t) +
                                    " has a non-finite vertex position");
      }
    }
    ++result.tested_triangles;
    if (IsDegenerate(a, b, c)) {
      ++result.degenerate_triangles;
      continue;
    }
    tested.index.push_back(static_cast<std::uint32_t>(t));
    tested.boxes.push_back({glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c))});
  }
  return tested;
}

// Cells about the size of a mean triangle box, at most ~2 cells per triangle.
Grid GridOver(std::span<const Box> boxes) {
  Box bounds = boxes[0];
  double mean_extent = 0.0;
  for (const Box& box : boxes) {
    bounds.lo = glm::min(bounds.lo, box.lo);
    bounds.hi = glm::max(bounds.hi, box.hi);
    const glm::vec3 extent = box.hi - box.lo;
    mean_extent += std::max({extent.x, extent.y, extent.z});
  }
  mean_extent /= static_cast<double>(boxes.size());
  const glm::vec3 span = bounds.hi - bounds.lo;
  const double largest_span = std::max({span.x, span.y, span.z});
  double cell = std::max(mean_extent, largest_span * 1e-6);
  if (!(cell > 0.0)) cell = 1.0;
  Grid grid;
  grid.origin = bounds.lo;
  const double max_cells = 2.0 * static_cast<double>(boxes.size()) + 64.0;
  for (;;) {
    double cells = 1.0;
    for (int k = 0; k < 3; ++k) {
      grid.size[static_cast<std::size_t>(k)] =
          std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(span[k] / cell)));
      cells *= static_cast<double>(grid.size[static_cast<std::size_t>(k)]);
    }
    if (cells <= max_cells) break;
    cell *= std::cbrt(cells / max_cells) * 1.01;
  }
  grid.inverse_cell = static_cast<float>(1.0 / cell);
  return grid;
}

// A triangle's entry in a cell: its box and low cell stored with it, so the
// pair loop reads memory in order.
struct Member {
  Box box;
  std::array<std::int32_t, 3> lo;
  std::uint32_t index;
};

// Cell -> members (compressed rows: cell c holds members[row_start[c], row_start[c + 1])).
struct CellMembers {
  std::vector<std::uint32_t> row_start;
  std::vector<Member> members;
};

CellMembers BucketByCell(const Grid& grid, std::span<const Box> boxes) {
  const auto cell_count = static_cast<std::size_t>(grid.size[0] * grid.size[1] * grid.size[2]);
  CellMembers cells;
  cells.row_start.assign(cell_count + 1, 0);
  std::vector<std::array<std::int64_t, 3>> lo_cell(boxes.size()), hi_cell(boxes.size());
  auto for_cells = [&](std::size_t i, auto&& visit) {
    for (std::int64_t z = lo_cell[i][2]; z <= hi_cell[i][2]; ++z) {
      for (std::int64_t y = lo_cell[i][1]; y <= hi_cell[i][1]; ++y) {
        for (std::int64_t x = lo_cell[i][0]; x <= hi_cell[i][0]; ++x) {
          visit(static_cast<std::size_t>(grid.Index({x, y, z})));
        }
      }
    }
  };
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    lo_cell[i] = grid.CellOf(boxes[i].lo);
    hi_cell[i] = grid.CellOf(boxes[i].hi);
    for_cells(i, [&](std::size_t c) { ++cells.row_start[c + 1]; });
  }
  for (std::size_t c = 0; c < cell_count; ++c) cells.row_start[c + 1] += cells.row_start[c];
  cells.members.resize(cells.row_start[cell_count]);
  std::vector<std::uint32_t> fill(cells.row_start.begin(), cells.row_start.end() - 1);
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const Member member{boxes[i],
                        {static_cast<std::int32_t>(lo_cell[i][0]), static_cast<std::int32_t>(lo_cell[i][1]),
                         static_cast<std::int32_t>(lo_cell[i][2])},
                        static_cast<std::uint32_t>(i)};
    for_cells(i, [&](std::size_t c) { cells.members[fill[c]++] = member; });
  }
  return cells;
}

bool BoxesOverlap(const Box& a, const Box& b) {
  return !(a.lo.x > b.hi.x || b.lo.x > a.hi.x || a.lo.y > b.hi.y || b.lo.y > a.hi.y || a.lo.z > b.hi.z ||
           b.lo.z > a.hi.z);
}

// Tests the pairs of cell (x, y, z) whose boxes' intersection has its low
// corner there: per axis the larger of the two boxes' low cells (CellOf is
// monotonic), so each overlapping pair is tested in exactly one cell.
void TestCell(std::array<std::int32_t, 3> cell, const Member* begin, const Member* end,
              std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
              std::span<const std::uint32_t> tested, const SelfIntersectionParams& params,
              SelfIntersectionResult& result) {
  for (const Member* a = begin; a < end; ++a) {
    const Triangle& ti = triangles[tested[a->index]];
    for (const Member* b = a + 1; b < end; ++b) {
      if (std::max(a->lo[0], b->lo[0]) != cell[0] || std::max(a->lo[1], b->lo[1]) != cell[1] ||
          std::max(a->lo[2], b->lo[2]) != cell[2]) {
        continue;
      }
      if (!BoxesOverlap(a->box, b->box)) continue;
      const Triangle& tj = triangles[tested[b->index]];
      bool shared = false;
      for (const std::uint32_t v : ti) shared = shared || v == tj[0] || v == tj[1] || v == tj[2];
      if (shared) continue;
      ++result.candidate_pairs;
      if (TrianglesCross(positions[ti[0]], positions[ti[1]], positions[ti[2]], positions[tj[0]], positions[tj[1]],
                         positions[tj[2]])) {
        ++result.intersecting_pairs;
        if (params.max_pairs > 0) {
          const std::uint32_t first = tested[a->index];
          const std::uint32_t second = tested[b->index];
          result.pairs.emplace_back(std::min(first, second), std::max(first, second));
        }
      }
    }
  }
}

}  // namespace

SelfIntersectionResult FindSelfIntersections(const Mesh& mesh, const SelfIntersectionParams& params) {
  const auto start = std::chrono::steady_clock::now();
  const std::span<const glm::vec3> positions = mesh.positions;
  const std::span<const Triangle> triangles = mesh.triangles;
  SelfIntersectionResult result;
  const TestedTriangles tested = CollectTestedTriangles(positions, triangles, params, result);
  if (tested.index.size() >= 2) {
    const Grid grid = GridOver(tested.boxes);
    const CellMembers cells = BucketByCell(grid, tested.boxes);
    for (std::int32_t z = 0; z < grid.size[2]; ++z) {
      for (std::int32_t y = 0; y < grid.size[1]; ++y) {
        for (std::int32_t x = 0; x < grid.size[0]; ++x) {
          const auto c = static_cast<std::size_t>(grid.Index({x, y, z}));
          TestCell({x, y, z}, cells.members.data() + cells.row_start[c], cells.members.data() + cells.row_start[c + 1],
                   positions, triangles, tested.index, params, result);
        }
      }
    }
  }
  std::sort(result.pairs.begin(), result.pairs.end());
  if (result.pairs.size() > params.max_pairs) result.pairs.resize(params.max_pairs);
  result.seconds = SecondsSince(start);
  return result;
}

float CrossingDepth(const glm::vec3& p1, const glm::vec3& q1, const glm::vec3& r1, const glm::vec3& p2,
                    const glm::vec3& q2, const glm::vec3& r2) {
  // The shorter reach of a, b, c to either side of the plane through p, q, r.
  const auto reach = [](const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& p,
                        const glm::vec3& q, const glm::vec3& r) {
    const glm::vec3 normal = glm::cross(q - p, r - p);
    const float length = glm::length(normal);
    if (!(length > 0.0f)) return 0.0f;
    const glm::vec3 unit = normal / length;
    const float da = glm::dot(a - p, unit);
    const float db = glm::dot(b - p, unit);
    const float dc = glm::dot(c - p, unit);
    const float above = std::max(0.0f, std::max(da, std::max(db, dc)));
    const float below = std::max(0.0f, -std::min(da, std::min(db, dc)));
    return std::min(above, below);
  };
  return std::min(reach(p1, q1, r1, p2, q2, r2), reach(p2, q2, r2, p1, q1, r1));
}

}  // namespace facerig
