// 2 linear + 2 Loop subdivisions as one sparse matrix (the construction of Mattos et al.):
// subdivision is linear in the control positions, so any per-vertex quantity
// authored on the control mesh (positions, displacements, weights) maps to
// the dense mesh through the same matrix, keeping per-vertex correspondence.
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "default_head/internal.h"
#include "facerig/offline/error.h"

namespace facerig::default_head {
namespace {

using Matrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;
using Edge = std::pair<std::uint32_t, std::uint32_t>;

Edge MakeEdge(std::uint32_t a, std::uint32_t b) { return a < b ? Edge{a, b} : Edge{b, a}; }

struct EdgeInfo {
  std::uint32_t new_vertex = 0;
  std::vector<std::uint32_t> opposite;  // 1 (boundary) or 2 (interior) opposite vertices
};

// The edges of `triangles` in first-use order, each with its new (midpoint)
// vertex numbered from vertex_count and its opposite vertices.
// std::map keeps the edge numbering independent of hashing: deterministic.
struct EdgeTable {
  std::map<Edge, EdgeInfo> edges;
  std::vector<Edge> order;
  std::uint32_t next = 0;  // vertex count after the step
};

EdgeTable NumberEdges(std::size_t vertex_count, const std::vector<Triangle>& triangles) {
  EdgeTable table;
  std::map<Edge, EdgeInfo>& edges = table.edges;
  std::vector<Edge>& edge_order = table.order;
  auto next = static_cast<std::uint32_t>(vertex_count);
  for (const Triangle& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const Edge e = MakeEdge(t[k], t[(k + 1) % 3]);
      auto [it, inserted] = edges.try_emplace(e);
      if (inserted) {
        it->second.new_vertex = next++;
        edge_order.push_back(e);
      }
      it->second.opposite.push_back(t[(k + 2) % 3]);
      if (it->second.opposite.size() > 2) throw InvalidInputError("Subdivide: non-manifold edge");
    }
  }
  table.next = next;
  return table;
}

// Rows of the old vertices: kept (linear steps, corners, where two openings
// touch), boundary (1, 6, 1) / 8, or Loop's interior weights.
void AddVertexRows(std::size_t vertex_count, EdgeTable& table, const std::vector<std::uint8_t>& corners, bool loop,
                   std::vector<Eigen::Triplet<double>>& entries) {
  std::map<Edge, EdgeInfo>& edges = table.edges;
  const std::vector<Edge>& edge_order = table.order;
  // Neighbours of each old vertex, and its boundary neighbours.
  std::vector<std::vector<std::uint32_t>> neighbours(vertex_count), boundary(vertex_count);
  for (const Edge& e : edge_order) {
    neighbours[e.first].push_back(e.second);
    neighbours[e.second].push_back(e.first);
    if (edges[e].opposite.size() == 1) {
      boundary[e.first].push_back(e.second);
      boundary[e.second].push_back(e.first);
    }
  }
  for (std::uint32_t v = 0; v < vertex_count; ++v) {
    const auto row = static_cast<Eigen::Index>(v);
    if (!loop || (v < corners.size() && corners[v]) || neighbours[v].empty()) {
      entries.emplace_back(row, row, 1.0);
    } else if (!boundary[v].empty()) {
      if (boundary[v].size() != 2) {  // a vertex where two openings touch: keep it
        entries.emplace_back(row, row, 1.0);
        continue;
      }
      entries.emplace_back(row, row, 0.75);
      entries.emplace_back(row, boundary[v][0], 0.125);
      entries.emplace_back(row, boundary[v][1], 0.125);
    } else {
      // Loop's original weights.
      const double n = static_cast<double>(neighbours[v].size());
      const double c = 0.375 + 0.25 * std::cos(2.0 * std::numbers::pi / n);
      const double beta = (0.625 - c * c) / n;
      entries.emplace_back(row, row, 1.0 - n * beta);
      for (std::uint32_t u : neighbours[v]) entries.emplace_back(row, u, beta);
    }
  }
}

// Rows of the new edge vertices: midpoints, or Loop's (3, 3, 1, 1) / 8 inside.
void AddEdgeRows(EdgeTable& table, bool loop, std::vector<Eigen::Triplet<double>>& entries) {
  std::map<Edge, EdgeInfo>& edges = table.edges;
  const std::vector<Edge>& edge_order = table.order;
  for (const Edge& e : edge_order) {
    const EdgeInfo& info = edges[e];
    const auto row = static_cast<Eigen::Index>(info.new_vertex);
    if (!loop || info.opposite.size() == 1) {
      entries.emplace_back(row, e.first, 0.5);
      entries.emplace_back(row, e.second, 0.5);
    } else {
      entries.emplace_back(row, e.first, 0.375);
      entries.emplace_back(row, e.second, 0.375);
      entries.emplace_back(row, info.opposite[0], 0.125);
      entries.emplace_back(row, info.opposite[1], 0.125);
    }
  }
}

// Each triangle into four through its edges' new vertices.
void RefineTriangles(const std::vector<Triangle>& triangles, std::map<Edge, EdgeInfo>& edges,
                     std::vector<Triangle>& refined) {
  refined.clear();
  refined.reserve(triangles.size() * 4);
  for (const Triangle& t : triangles) {
    const std::uint32_t ab = edges[MakeEdge(t[0], t[1])].new_vertex;
    const std::uint32_t bc = edges[MakeEdge(t[1], t[2])].new_vertex;
    const std::uint32_t ca = edges[MakeEdge(t[2], t[0])].new_vertex;
    refined.push_back({t[0], ab, ca});
    refined.push_back({t[1], bc, ab});
    refined.push_back({t[2], ca, bc});
    refined.push_back({ab, bc, ca});
  }
}

// One step: returns the (V + E) x V matrix and the refined triangles.
Matrix Step(std::size_t vertex_count, const std::vector<Triangle>& triangles,
            const std::vector<std::uint8_t>& corners, bool loop, std::vector<Triangle>& refined) {
  EdgeTable table = NumberEdges(vertex_count, triangles);
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(vertex_count * 7 + table.order.size() * 4);
  AddVertexRows(vertex_count, table, corners, loop, entries);
  AddEdgeRows(table, loop, entries);
  Matrix step(static_cast<Eigen::Index>(table.next), static_cast<Eigen::Index>(vertex_count));
  step.setFromTriplets(entries.begin(), entries.end());
  RefineTriangles(triangles, table.edges, refined);
  return step;
}

}  // namespace

Subdivision Subdivide(std::size_t vertex_count, const std::vector<Triangle>& triangles,
                      const std::vector<std::uint8_t>& corners, int linear_steps, int loop_steps) {
  Subdivision result;
  result.matrix.resize(static_cast<Eigen::Index>(vertex_count), static_cast<Eigen::Index>(vertex_count));
  result.matrix.setIdentity();
  result.triangles = triangles;
  std::vector<std::uint8_t> level_corners = corners;
  std::size_t count = vertex_count;
  for (int s = 0; s < linear_steps + loop_steps; ++s) {
    std::vector<Triangle> refined;
    const Matrix step = Step(count, result.triangles, level_corners, s >= linear_steps, refined);
    result.matrix = Matrix(step * result.matrix);
    result.matrix.prune(0.0);
    result.triangles = std::move(refined);
    count = static_cast<std::size_t>(step.rows());
    level_corners.resize(count, 0);  // new edge vertices are never corners
  }
  return result;
}

std::vector<double> Apply(const Subdivision& s, const std::vector<double>& control) {
  const Eigen::VectorXd in = Eigen::Map<const Eigen::VectorXd>(control.data(), static_cast<Eigen::Index>(control.size()));
  const Eigen::VectorXd out = s.matrix * in;
  return {out.data(), out.data() + out.size()};
}

std::vector<glm::dvec3> Apply(const Subdivision& s, const std::vector<glm::dvec3>& control) {
  Eigen::MatrixXd in(static_cast<Eigen::Index>(control.size()), 3);
  for (std::size_t i = 0; i < control.size(); ++i) {
    for (int c = 0; c < 3; ++c) in(static_cast<Eigen::Index>(i), c) = control[i][c];
  }
  const Eigen::MatrixXd out = s.matrix * in;
  std::vector<glm::dvec3> result(static_cast<std::size_t>(out.rows()));
  for (std::size_t i = 0; i < result.size(); ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    result[i] = {out(r, 0), out(r, 1), out(r, 2)};
  }
  return result;
}

}  // namespace facerig::default_head
