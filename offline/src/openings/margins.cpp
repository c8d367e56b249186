#include "facerig/offline/openings/margins.h"
#include "facerig/offline/geometry/stats.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <glm/geometric.hpp>

#include "facerig/offline/error.h"
#include "facerig/offline/geometry/mesh_components.h"
#include "geometry/mesh_edges.h"
#include "openings/contacts.h"

namespace facerig {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// A boundary edge of the target (used by one triangle: the rim of a hole) and
// the direction from it into the hole, in its triangle's plane.
struct RimEdge {
  glm::vec3 a;
  glm::vec3 b;
  glm::vec3 into_opening;
};

std::vector<RimEdge> RimEdges(std::span<const glm::vec3> positions, std::span<const Triangle> triangles) {
  std::vector<RimEdge> rims;
  for (const BoundarySide& side : BoundarySides(triangles)) {
    const glm::vec3 a = positions[side.a], b = positions[side.b];
    const glm::vec3 edge = b - a;
    glm::vec3 inward = positions[side.opposite] - a;
    const float edge_length2 = glm::dot(edge, edge);
    if (edge_length2 > 0.0f) inward -= glm::dot(inward, edge) / edge_length2 * edge;
    const float length = glm::length(inward);
    if (length > 0.0f) rims.push_back({a, b, -inward / length});
  }
  return rims;
}

glm::vec3 ClosestOnSegment(glm::vec3 p, glm::vec3 a, glm::vec3 b) {
  const glm::vec3 ab = b - a;
  const float length2 = glm::dot(ab, ab);
  if (!(length2 > 0.0f)) return a;
  return a + std::clamp(glm::dot(p - a, ab) / length2, 0.0f, 1.0f) * ab;
}

}  // namespace

std::vector<OpeningMargin> FindOpeningMargins(const Rig& template_rig, const OpeningParams& params) {
  const std::span<const glm::vec3> neutral = template_rig.positions();
  const std::size_t n = neutral.size();
  std::vector<std::uint32_t> component;
  ConnectedComponents(n, template_rig.triangles(), component);
  const ContactFinder finder(neutral, template_rig.triangles(), component, params);
  ContactFinder::Scratch scratch;
  const std::vector<std::int32_t> every_vertex(n, 0);  // each a moving end (free_index >= 0)
  std::vector<glm::vec3> expression;
  std::vector<OpeningContact> contacts;
  std::vector<std::uint32_t> partner_of(n, kNone);
  for (std::size_t s = 0; s < template_rig.shape_count(); ++s) {
    const BlendShapeView shape = template_rig.shape(s);
    expression.assign(neutral.begin(), neutral.end());
    float largest = 0.0f;
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      expression[shape.vertex_indices[i]] += shape.position_deltas[i];
      largest = std::max(largest, glm::length(shape.position_deltas[i]));
    }
    if (!(largest > 0.0f)) continue;
    finder.Find(expression, largest, every_vertex, contacts, scratch);
    for (const OpeningContact& contact : contacts) {
      if (partner_of[contact.moving] == kNone) partner_of[contact.moving] = contact.partner;
      if (partner_of[contact.partner] == kNone) partner_of[contact.partner] = contact.moving;
    }
  }
  std::vector<OpeningMargin> margins;
  for (std::size_t v = 0; v < n; ++v) {
    if (partner_of[v] != kNone) margins.push_back({static_cast<std::uint32_t>(v), partner_of[v]});
  }
  return margins;
}

namespace {

// Each margin vertex onto the nearest rim point that faces the same way.
std::vector<std::optional<glm::vec3>> NearestRimPoints(std::span<const glm::vec3> fitted,
                                                       std::span<const OpeningMargin> margins,
                                                       std::span<const RimEdge> rims,
                                                       const OpeningParams& params) {
  std::vector<std::optional<glm::vec3>> rim_point(fitted.size());
  for (const OpeningMargin& margin : margins) {
    const glm::vec3 p = fitted[margin.vertex];
    const glm::vec3 across = fitted[margin.partner] - p;
    const float opening = glm::length(across);
    if (!(opening > 0.0f)) continue;
    const glm::vec3 direction = across / opening;
    float best = params.margin_max_distance * opening;
    for (const RimEdge& rim : rims) {
      if (glm::dot(direction, rim.into_opening) < params.margin_min_facing) continue;
      const glm::vec3 x = ClosestOnSegment(p, rim.a, rim.b);
      const float distance = glm::length(x - p);
      if (distance < best) {
        best = distance;
        rim_point[margin.vertex] = x;
      }
    }
  }
  return rim_point;
}

struct Match {
  std::uint32_t vertex;
  glm::vec3 correction;
  float opening;
};

// Kept where the partner found a rim point too, across an opening of
// about the same size and direction (OpeningParams::margin_min_opening_ratio).
std::vector<Match> MatchMargins(std::span<const glm::vec3> fitted, std::span<const OpeningMargin> margins,
                                const std::vector<std::optional<glm::vec3>>& rim_point,
                                const OpeningParams& params) {
  std::vector<Match> matches;
  for (const OpeningMargin& margin : margins) {
    if (!rim_point[margin.vertex] || !rim_point[margin.partner]) continue;
    const glm::vec3 across = fitted[margin.partner] - fitted[margin.vertex];
    const glm::vec3 rim_across = *rim_point[margin.partner] - *rim_point[margin.vertex];
    const float opening = glm::length(across);
    const float rim_opening = glm::length(rim_across);
    const float ratio = params.margin_min_opening_ratio;
    if (rim_opening < ratio * opening || rim_opening > opening / ratio) continue;
    if (glm::dot(across, rim_across) < params.margin_min_facing * opening * rim_opening) continue;
    matches.push_back({margin.vertex, *rim_point[margin.vertex] - fitted[margin.vertex], opening});
  }
  return matches;
}

constexpr std::int32_t kFixed = -2;
constexpr std::int32_t kOutside = -1;

// The band: vertices within `reach` of an aligned margin vertex along the
// template's edges (multi-source Dijkstra), each with its unknown index; the
// aligned margins fixed at their corrections.
struct CorrectionBand {
  std::vector<std::uint32_t> begin, neighbours;  // template vertex neighbours
  std::vector<std::int32_t> unknown;             // band vertex -> unknown index, else kFixed / kOutside
  std::vector<glm::vec3> correction;
  std::vector<std::uint32_t> band;
};

CorrectionBand BandAround(std::span<const glm::vec3> fitted, std::span<const Triangle> template_triangles,
                          std::span<const Match> matches, float reach) {
  const std::size_t n = fitted.size();
  CorrectionBand b;
  VertexNeighbours(n, template_triangles, b.begin, b.neighbours);
  b.unknown.assign(n, kOutside);
  b.correction.assign(n, glm::vec3(0.0f));
  std::vector<std::uint32_t> sources;
  for (const Match& m : matches) {
    b.unknown[m.vertex] = kFixed;
    b.correction[m.vertex] = m.correction;
    sources.push_back(m.vertex);
  }
  const std::vector<float> reaches(sources.size(), reach);
  for (const EdgeReach& at : VerticesWithinReach(fitted, b.begin, b.neighbours, sources, reaches)) {
    if (b.unknown[at.vertex] != kOutside) continue;
    b.unknown[at.vertex] = static_cast<std::int32_t>(b.band.size());
    b.band.push_back(at.vertex);
  }
  return b;
}

// Harmonic in the band (uniform weights): the aligned margins fixed, zero
// beyond the band. Leaves the band's corrections at zero if the solve fails.
void SolveHarmonicBand(CorrectionBand& b) {
  if (b.band.empty()) return;
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(b.band.size()), 3);
  for (std::size_t i = 0; i < b.band.size(); ++i) {
    const std::uint32_t v = b.band[i];
    const auto row = static_cast<Eigen::Index>(i);
    triplets.emplace_back(row, row, static_cast<double>(b.begin[v + 1] - b.begin[v]));
    for (std::uint32_t k = b.begin[v]; k < b.begin[v + 1]; ++k) {
      const std::uint32_t w = b.neighbours[k];
      if (b.unknown[w] >= 0) {
        triplets.emplace_back(row, b.unknown[w], -1.0);
      } else if (b.unknown[w] == kFixed) {
        rhs.row(row) += Eigen::RowVector3d(b.correction[w].x, b.correction[w].y, b.correction[w].z);
      }
    }
  }
  Eigen::SparseMatrix<double> laplacian(static_cast<Eigen::Index>(b.band.size()),
                                        static_cast<Eigen::Index>(b.band.size()));
  laplacian.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(laplacian);
  if (solver.info() != Eigen::Success) return;
  const Eigen::MatrixXd solution = solver.solve(rhs);
  for (std::size_t i = 0; i < b.band.size(); ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    b.correction[b.band[i]] = glm::vec3(static_cast<float>(solution(row, 0)), static_cast<float>(solution(row, 1)),
                                        static_cast<float>(solution(row, 2)));
  }
}

void SummariseMatches(std::span<const Match> matches, MarginAlignmentResult& result) {
  result.aligned_vertices = matches.size();
  for (const Match& m : matches) result.aligned.push_back(m.vertex);
  std::sort(result.aligned.begin(), result.aligned.end());
  for (const Match& m : matches) {
    const double size = glm::length(m.correction);
    result.mean_correction += size / static_cast<double>(matches.size());
    result.max_correction = std::max(result.max_correction, size);
  }
}

}  // namespace

MarginAlignmentResult AlignMarginsToOpenings(std::span<glm::vec3> fitted, std::span<const Triangle> template_triangles,
                                             std::span<const OpeningMargin> margins,
                                             std::span<const glm::vec3> target_positions,
                                             std::span<const Triangle> target_triangles,
                                             const OpeningParams& params) {
  MarginAlignmentResult result;
  const std::vector<RimEdge> rims = RimEdges(target_positions, target_triangles);
  if (rims.empty() || margins.empty()) return result;

  const std::vector<std::optional<glm::vec3>> rim_point = NearestRimPoints(fitted, margins, rims, params);
  std::vector<Match> matches = MatchMargins(fitted, margins, rim_point, params);
  if (matches.empty()) return result;
  std::vector<float> sizes, openings;
  for (const Match& m : matches) {
    sizes.push_back(glm::length(m.correction));
    openings.push_back(m.opening);
  }
  const float limit = params.margin_max_correction_over_median * Median(sizes);
  std::erase_if(matches, [&](const Match& m) { return glm::length(m.correction) > limit; });
  const float reach = params.margin_reach * Median(openings);

  CorrectionBand band = BandAround(fitted, template_triangles, matches, reach);
  SolveHarmonicBand(band);
  for (std::size_t v = 0; v < fitted.size(); ++v) {
    if (band.unknown[v] == kOutside) continue;
    fitted[v] += band.correction[v];
    if (glm::length(band.correction[v]) > 0.0f) ++result.moved_vertices;
  }
  SummariseMatches(matches, result);
  return result;
}

std::vector<MarginDirection> MarginDirections(std::span<const OpeningMargin> margins,
                                              std::span<const std::uint32_t> aligned,
                                              std::span<const glm::vec3> fitted) {
  std::vector<MarginDirection> directions;
  for (const OpeningMargin& margin : margins) {
    if (!std::binary_search(aligned.begin(), aligned.end(), margin.vertex)) continue;
    const glm::vec3 across = fitted[margin.partner] - fitted[margin.vertex];
    const float length = glm::length(across);
    if (length > 0.0f) directions.push_back({margin.vertex, across / length});
  }
  return directions;
}

}  // namespace facerig
