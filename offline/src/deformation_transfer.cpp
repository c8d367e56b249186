#include "facerig/offline/deformation_transfer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <numeric>
#include <optional>
#include <thread>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <glm/common.hpp>

#include "expression_contacts.h"

namespace facerig {

namespace {

using Clock = std::chrono::steady_clock;
using Mat32 = Eigen::Matrix<double, 3, 2>;
using Mat23 = Eigen::Matrix<double, 2, 3>;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

Eigen::Vector3d ToEigen(glm::vec3 p) { return {p.x, p.y, p.z}; }

Mat32 Edges(std::span<const glm::vec3> positions, const Triangle& t) {
  const Eigen::Vector3d p0 = ToEigen(positions[t[0]]);
  Mat32 e;
  e.col(0) = ToEigen(positions[t[1]]) - p0;
  e.col(1) = ToEigen(positions[t[2]]) - p0;
  return e;
}

// Local frame [e1 e2 n] of paper 000 eq. 1; with scaled_normal the normal is
// Sumner & Popovic's 4th vertex offset (e1 x e2) / sqrt(|e1 x e2|).
Eigen::Matrix3d Frame(const Mat32& edges, bool scaled_normal) {
  Eigen::Matrix3d frame;
  frame.leftCols<2>() = edges;
  const Eigen::Vector3d cross = edges.col(0).cross(edges.col(1));
  const double length = cross.norm();
  if (length > 0.0) {
    frame.col(2) = cross / (scaled_normal ? std::sqrt(length) : length);
  } else {
    frame.col(2).setZero();
  }
  return frame;
}

// Smallest over largest eigenvalue of the 2x2 Gram matrix of a triangle's edges
// (1 for an equilateral-ish frame, 0 for a degenerate one).
double GramRatio(const Mat32& edges) {
  const Eigen::Matrix2d gram = edges.transpose() * edges;
  const double trace = gram.trace();
  if (!(trace > 0.0)) return 0.0;
  const double det = std::max(0.0, gram.determinant());
  const double disc = std::sqrt(std::max(0.0, 0.25 * trace * trace - det));
  const double largest = 0.5 * trace + disc;
  return (0.5 * trace - disc) / largest;
}

void CheckPositions(std::span<const glm::vec3> positions, std::size_t vertex_count,
                    const std::string& mesh) {
  if (positions.size() != vertex_count) {
    throw TransferInputError(mesh, "has " + std::to_string(positions.size()) +
                                       " vertices, expected " + std::to_string(vertex_count));
  }
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const glm::vec3 p = positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw TransferInputError(mesh, "vertex " + std::to_string(v) + " is not finite");
    }
  }
}

float BoundingDiagonal(std::span<const glm::vec3> positions) {
  if (positions.empty()) return 0.0f;
  glm::vec3 lo = positions[0];
  glm::vec3 hi = positions[0];
  for (const glm::vec3& p : positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::vec3 d = hi - lo;
  return std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
}

}  // namespace

TransferInputError::TransferInputError(std::string mesh, const std::string& message)
    : InvalidInputError(mesh + ": " + message), mesh_(std::move(mesh)) {}

const char* ToString(TransferMode mode) {
  switch (mode) {
    case TransferMode::kClassic: return "classic";
    case TransferMode::kIdentityGradient: return "identity";
  }
  return "unknown";
}

struct DeformationTransferData::Impl {
  static constexpr char kPinnedRigid = 2;  // Scratch::pinned: placed by PinRigidMotions
  struct TriangleData {
    Eigen::Matrix3d source_frame_inverse;  // V(S_0)^-1
    Eigen::Matrix3d identity_gradient;     // V(T_0) V(S_0)^-1 (identity mode)
    Mat32 target_edges;                    // E(T_0)
    Mat23 rhs_operator;                    // w (W W^T) B, W = R^-1 Q^T of E(T_0)
    bool source_degenerate = false;
  };

  TransferMode mode = TransferMode::kClassic;
  bool scaled_normal = true;
  double displacement_scale = 1.0;
  std::vector<Triangle> triangles;
  std::vector<TriangleData> triangle_data;
  std::vector<glm::vec3> source_neutral;
  std::vector<glm::vec3> target_neutral;
  std::vector<std::int32_t> free_index;  // -1 for anchors
  std::vector<std::uint32_t> anchors;    // includes gauge vertices of floating parts
  std::vector<std::vector<std::uint32_t>> floating_parts;
  Eigen::SparseMatrix<double> coupling;  // L_fa: free rows x anchor columns
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  double total_weight = 0.0;
  double prior = 0.0;  // absolute weight of the displacement prior

  // Still pinning (params.still_fraction > 0): the whole #V x #V system, the
  // anchors given or found static (without gauges), and each connected
  // part's vertices and gauge vertex (nearest its centroid).
  double still_fraction = 0.0;
  double rigid_tolerance = 0.0;
  double contact_weight = 0.0;  // absolute
  bool close_contacts = true;
  std::optional<ExpressionContactFinder> contact_finder;  // with contact_weight > 0 (and still pinning)
  Eigen::SparseMatrix<double> full_system;
  std::vector<char> is_static_anchor;
  std::vector<std::uint32_t> component_of_vertex;
  std::vector<std::vector<std::uint32_t>> component_members;
  std::vector<std::uint32_t> component_gauge;

  // Desired edges (3x2) of triangle j in the expression.
  Mat32 DesiredEdges(std::size_t j, std::span<const glm::vec3> expression) const {
    const TriangleData& d = triangle_data[j];
    const Mat32 expression_edges = Edges(expression, triangles[j]);
    if (d.source_degenerate) {
      // No usable gradient: carry the edge differences over (exact for a same-shape target).
      return d.target_edges +
             displacement_scale * (expression_edges - Edges(source_neutral, triangles[j]));
    }
    if (mode == TransferMode::kClassic) {
      const Eigen::Matrix3d gradient =
          Frame(expression_edges, scaled_normal) * d.source_frame_inverse;
      return gradient * d.target_edges;
    }
    return d.identity_gradient * expression_edges;
  }

  glm::vec3 AnchorPosition(std::uint32_t v, std::span<const glm::vec3> expression) const {
    return target_neutral[v] +
           static_cast<float>(displacement_scale) * (expression[v] - source_neutral[v]);
  }

  struct Scratch {
    std::vector<Mat32> desired;        // per triangle
    std::vector<double> accumulated;   // 3 #V
    Eigen::MatrixXd anchor_positions;  // #anchors x 3
    Eigen::MatrixXd rhs;               // #free x 3
    Eigen::MatrixXd solution;
    // Still pinning: this expression's pinned vertices and system.
    std::vector<char> pinned;
    std::vector<std::int32_t> free_index;
    std::vector<std::uint32_t> floating_components;
    std::vector<std::uint32_t> moving;  // one part's unpinned vertices
    struct RigidFit {
      Eigen::Matrix4d transform;  // template rest -> expression
      std::vector<std::uint32_t> vertices;
      std::size_t group;  // index of the first fit with the same motion
    };
    std::vector<RigidFit> rigid_fits;
    std::vector<ExpressionContact> contacts;
    ExpressionContactFinder::Scratch contact_scratch;
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::SparseMatrix<double> system;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  };
  // One expression: returns the residual; scratch.contacts holds the contacts kept.
  double Solve(std::span<const glm::vec3> expression, std::vector<glm::vec3>& out,
               Scratch& scratch) const;
  // The free vertices' positions with this expression's still vertices pinned.
  void SolveStillPinned(std::span<const glm::vec3> expression, const double* accumulated,
                        std::vector<glm::vec3>& out, Scratch& scratch) const;
  // Pins the unpinned vertices of each part where the template moves them as
  // one rigid body (pinned = kPinnedRigid), placing them rigidly in out.
  void PinRigidMotions(std::span<const glm::vec3> expression, std::vector<glm::vec3>& out,
                       Scratch& scratch) const;
  // Translates a part without anchors so that its mean displacement is
  // displacement_scale times the template's.
  void PlaceFloatingPart(std::span<const std::uint32_t> part, std::span<const glm::vec3> expression,
                         std::vector<glm::vec3>& out) const;
  // The weighted root-mean-square gradient residual of a solved expression.
  double Residual(std::span<const glm::vec3> out, const Scratch& scratch) const;
};

DeformationTransferData::DeformationTransferData() = default;
DeformationTransferData::~DeformationTransferData() = default;
DeformationTransferData::DeformationTransferData(DeformationTransferData&&) noexcept = default;
DeformationTransferData& DeformationTransferData::operator=(DeformationTransferData&&) noexcept =
    default;

std::size_t ConnectedComponents(std::size_t vertex_count, std::span<const Triangle> triangles,
                                std::vector<std::uint32_t>& component_of_vertex) {
  std::vector<std::uint32_t> parent(vertex_count);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&parent](std::uint32_t v) {
    while (parent[v] != v) {
      parent[v] = parent[parent[v]];
      v = parent[v];
    }
    return v;
  };
  for (const Triangle& t : triangles) {
    for (int k = 1; k < 3; ++k) {
      const std::uint32_t a = find(t[0]);
      const std::uint32_t b = find(t[static_cast<std::size_t>(k)]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  component_of_vertex.assign(vertex_count, 0);
  std::vector<std::uint32_t> label(vertex_count, UINT32_MAX);
  std::uint32_t count = 0;
  for (std::uint32_t v = 0; v < vertex_count; ++v) {
    const std::uint32_t root = find(v);
    if (label[root] == UINT32_MAX) label[root] = count++;
    component_of_vertex[v] = label[root];
  }
  return count;
}

void PrecomputeDeformationTransfer(std::span<const glm::vec3> source_neutral,
                                   std::span<const glm::vec3> target_neutral,
                                   std::span<const Triangle> triangles,
                                   std::span<const std::vector<glm::vec3>> source_expressions,
                                   const DeformationTransferParams& params,
                                   DeformationTransferData& data) {
  const Clock::time_point start = Clock::now();
  const std::size_t n = source_neutral.size();
  if (n == 0 || triangles.empty()) {
    throw TransferInputError("source neutral", "needs vertices and triangles");
  }
  CheckPositions(source_neutral, n, "source neutral");
  CheckPositions(target_neutral, n, "target neutral");
  for (std::size_t k = 0; k < source_expressions.size(); ++k) {
    CheckPositions(source_expressions[k], n, "source expression " + std::to_string(k));
  }
  for (std::size_t j = 0; j < triangles.size(); ++j) {
    for (std::uint32_t v : triangles[j]) {
      if (v >= n) {
        throw TransferInputError("triangles", "triangle " + std::to_string(j) + " uses vertex " +
                                                  std::to_string(v) + " >= " + std::to_string(n));
      }
    }
  }
  if (!(params.displacement_scale > 0.0f) || !std::isfinite(params.displacement_scale)) {
    throw TransferInputError("params", "displacement_scale must be finite and > 0");
  }
  if (!(params.displacement_prior >= 0.0) || !std::isfinite(params.displacement_prior)) {
    throw TransferInputError("params", "displacement_prior must be finite and >= 0");
  }
  if (!(params.min_gram_ratio > 0.0) || !(params.min_gram_ratio < 1.0)) {
    throw TransferInputError("params", "min_gram_ratio must be in (0, 1)");
  }
  if (!(params.still_fraction >= 0.0) || !(params.still_fraction < 1.0)) {
    throw TransferInputError("params", "still_fraction must be in [0, 1)");
  }
  if (!(params.rigid_tolerance >= 0.0) || !(params.rigid_tolerance < 1.0)) {
    throw TransferInputError("params", "rigid_tolerance must be in [0, 1)");
  }
  if (!(params.contact_weight >= 0.0) || !std::isfinite(params.contact_weight)) {
    throw TransferInputError("params", "contact_weight must be finite and >= 0");
  }

  auto impl = std::make_unique<DeformationTransferData::Impl>();
  impl->mode = params.mode;
  impl->scaled_normal = params.scaled_normal;
  impl->displacement_scale = params.displacement_scale;
  impl->still_fraction = params.still_fraction;
  impl->rigid_tolerance = params.rigid_tolerance;
  impl->triangles.assign(triangles.begin(), triangles.end());
  impl->source_neutral.assign(source_neutral.begin(), source_neutral.end());
  impl->target_neutral.assign(target_neutral.begin(), target_neutral.end());

  // Anchors: the given list, or the template's static set.
  std::vector<char> is_anchor(n, 0);
  if (!params.anchor_vertices.empty()) {
    for (std::uint32_t v : params.anchor_vertices) {
      if (v >= n) {
        throw TransferInputError("anchor vertices", "vertex " + std::to_string(v) + " >= " +
                                                        std::to_string(n));
      }
      is_anchor[v] = 1;
    }
  } else {
    if (source_expressions.empty()) {
      throw TransferInputError("source expressions",
                               "needed to find the static anchors when none are given");
    }
    const float limit = params.static_threshold * BoundingDiagonal(source_neutral);
    const float limit2 = limit * limit;
    std::vector<float> largest(n, 0.0f);
    for (const std::vector<glm::vec3>& expression : source_expressions) {
      for (std::size_t v = 0; v < n; ++v) {
        const glm::vec3 d = expression[v] - source_neutral[v];
        largest[v] = std::max(largest[v], d.x * d.x + d.y * d.y + d.z * d.z);
      }
    }
    for (std::size_t v = 0; v < n; ++v) is_anchor[v] = largest[v] <= limit2 ? 1 : 0;
  }
  std::vector<char> used(n, 0);
  for (const Triangle& t : triangles) {
    for (std::uint32_t v : t) used[v] = 1;
  }
  for (std::size_t v = 0; v < n; ++v) {
    if (!used[v]) is_anchor[v] = 1;
  }
  const bool still_pinning = params.still_fraction > 0.0;
  if (still_pinning) impl->is_static_anchor = is_anchor;

  // Every connected part needs an anchor; parts without one get a gauge vertex
  // (the one nearest the part's centroid) and are placed by mean displacement.
  std::vector<std::uint32_t> component;
  const std::size_t component_count = ConnectedComponents(n, triangles, component);
  std::vector<char> anchored(component_count, 0);
  for (std::size_t v = 0; v < n; ++v) {
    if (is_anchor[v]) anchored[component[v]] = 1;
  }
  std::vector<std::vector<std::uint32_t>> members(component_count);
  for (std::uint32_t v = 0; v < n; ++v) {
    if (!anchored[component[v]]) members[component[v]].push_back(v);
  }
  auto gauge_of = [&target_neutral](std::span<const std::uint32_t> part) {
    glm::dvec3 centroid(0.0);
    for (std::uint32_t v : part) centroid += glm::dvec3(target_neutral[v]);
    centroid /= static_cast<double>(part.size());
    std::uint32_t gauge = part[0];
    double best = 1e300;
    for (std::uint32_t v : part) {
      const glm::dvec3 d = glm::dvec3(target_neutral[v]) - centroid;
      const double dist = d.x * d.x + d.y * d.y + d.z * d.z;
      if (dist < best) {
        best = dist;
        gauge = v;
      }
    }
    return gauge;
  };
  if (still_pinning) {
    // Which parts float depends on the expression: keep every part's gauge.
    impl->component_of_vertex = component;
    impl->component_members.resize(component_count);
    for (std::uint32_t v = 0; v < n; ++v) impl->component_members[component[v]].push_back(v);
    for (const std::vector<std::uint32_t>& part : impl->component_members) {
      impl->component_gauge.push_back(gauge_of(part));
    }
  }
  for (std::size_t c = 0; c < component_count; ++c) {
    if (anchored[c]) continue;
    is_anchor[gauge_of(members[c])] = 1;
    impl->floating_parts.push_back(std::move(members[c]));
  }

  impl->free_index.assign(n, -1);
  std::vector<std::int32_t> anchor_index(n, -1);
  std::int32_t free_count = 0;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (is_anchor[v]) {
      anchor_index[v] = static_cast<std::int32_t>(impl->anchors.size());
      impl->anchors.push_back(v);
    } else {
      impl->free_index[v] = free_count++;
    }
  }

  // Per-triangle data and the normal equations (U^T U restricted to the free
  // vertices, and its coupling to the anchors).
  double mean_area = 0.0;
  double mean_edge2 = 0.0;
  for (const Triangle& t : triangles) {
    const Mat32 e = Edges(target_neutral, t);
    mean_area += 0.5 * e.col(0).cross(e.col(1)).norm();
    mean_edge2 += 0.5 * e.colwise().squaredNorm().sum();
  }
  mean_area /= static_cast<double>(triangles.size());
  mean_edge2 /= static_cast<double>(triangles.size());
  if (!(mean_edge2 > 0.0)) throw TransferInputError("target neutral", "all triangles are points");

  Mat23 b;  // edge operator: (e1, e2) = X * B^T over the triangle's 3 vertices
  b << -1.0, 1.0, 0.0, -1.0, 0.0, 1.0;
  const double ratio = params.min_gram_ratio;
  std::vector<Eigen::Triplet<double>> free_triplets;
  std::vector<Eigen::Triplet<double>> coupling_triplets;
  std::vector<Eigen::Triplet<double>> full_triplets;
  free_triplets.reserve(triangles.size() * 9);
  if (still_pinning) full_triplets.reserve(triangles.size() * 9);
  impl->triangle_data.resize(triangles.size());
  std::size_t regularized = 0;
  for (std::size_t j = 0; j < triangles.size(); ++j) {
    const Triangle& t = triangles[j];
    DeformationTransferData::Impl::TriangleData& d = impl->triangle_data[j];
    d.target_edges = Edges(target_neutral, t);
    const Mat32 source_edges = Edges(source_neutral, t);

    d.source_degenerate = GramRatio(source_edges) < ratio;
    if (!d.source_degenerate) {
      d.source_frame_inverse = Frame(source_edges, params.scaled_normal).inverse();
      d.identity_gradient = Frame(d.target_edges, params.scaled_normal) * d.source_frame_inverse;
      d.source_degenerate = !d.source_frame_inverse.allFinite() || !d.identity_gradient.allFinite();
    }
    if (d.source_degenerate) {
      d.source_frame_inverse.setIdentity();
      d.identity_gradient.setIdentity();
    }

    // W = R^-1 Q^T from the QR of the target's edges (Algorithm 1, line 15),
    // with R's diagonal clamped so needles and points stay bounded.
    Eigen::HouseholderQR<Mat32> qr(d.target_edges);
    Eigen::Matrix2d r = qr.matrixQR().topRows<2>().triangularView<Eigen::Upper>();
    const double r0_min = std::sqrt(1e-6 * mean_edge2);
    bool clamped = false;
    if (std::abs(r(0, 0)) < r0_min) {
      r(0, 0) = r0_min;
      r(0, 1) = 0.0;
      clamped = true;
    }
    const double r1_min = std::max(std::sqrt(ratio) * std::abs(r(0, 0)), r0_min);
    if (std::abs(r(1, 1)) < r1_min) {
      r(1, 1) = r(1, 1) < 0.0 ? -r1_min : r1_min;
      clamped = true;
    }
    if (clamped || d.source_degenerate) ++regularized;
    const Mat32 q = qr.householderQ() * Mat32::Identity();
    const Mat23 w = r.inverse() * q.transpose();  // 2x3
    const Eigen::Matrix2d metric = w * w.transpose();  // (E^T E)^-1, regularized
    double weight = 1.0;
    if (params.area_weighted) {
      const double area = 0.5 * d.target_edges.col(0).cross(d.target_edges.col(1)).norm();
      weight = std::max(area, 1e-3 * mean_area) / mean_area;
    }
    impl->total_weight += weight;
    d.rhs_operator = weight * metric * b;
    const Eigen::Matrix3d local = b.transpose() * d.rhs_operator;  // w B^T M B
    if (still_pinning) {
      for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col) {
          full_triplets.emplace_back(t[static_cast<std::size_t>(row)],
                                     t[static_cast<std::size_t>(col)], local(row, col));
        }
      }
    }
    for (int row = 0; row < 3; ++row) {
      const std::int32_t fr = impl->free_index[t[static_cast<std::size_t>(row)]];
      if (fr < 0) continue;
      for (int col = 0; col < 3; ++col) {
        const std::uint32_t vc = t[static_cast<std::size_t>(col)];
        if (impl->free_index[vc] >= 0) {
          free_triplets.emplace_back(fr, impl->free_index[vc], local(row, col));
        } else {
          coupling_triplets.emplace_back(fr, anchor_index[vc], local(row, col));
        }
      }
    }
  }

  Eigen::SparseMatrix<double> system(free_count, free_count);
  system.setFromTriplets(free_triplets.begin(), free_triplets.end());
  if (params.displacement_prior > 0.0 && free_count > 0) {
    impl->prior = params.displacement_prior * system.diagonal().mean();
    for (std::int32_t f = 0; f < free_count; ++f) system.coeffRef(f, f) += impl->prior;
  }
  impl->coupling.resize(free_count, static_cast<Eigen::Index>(impl->anchors.size()));
  impl->coupling.setFromTriplets(coupling_triplets.begin(), coupling_triplets.end());
  if (still_pinning) {
    impl->full_system.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    impl->full_system.setFromTriplets(full_triplets.begin(), full_triplets.end());
    if (params.displacement_prior > 0.0) {
      impl->prior = params.displacement_prior * impl->full_system.diagonal().mean();
    }
    if (params.contact_weight > 0.0) {
      impl->contact_weight = params.contact_weight * impl->full_system.diagonal().mean();
      impl->close_contacts = params.close_contacts;
      impl->contact_finder.emplace(impl->source_neutral, impl->triangles, impl->component_of_vertex);
    }
  }

  const Clock::time_point factorize_start = Clock::now();
  // With still pinning each expression factorizes its own system.
  if (free_count > 0 && !still_pinning) {
    impl->solver.compute(system);
    if (impl->solver.info() != Eigen::Success) {
      throw TransferSolverError("deformation transfer: the sparse Cholesky factorization of " +
                                std::to_string(free_count) + " unknowns failed");
    }
  }
  data.factorize_seconds = SecondsSince(factorize_start);

  data.vertex_count = n;
  data.triangle_count = triangles.size();
  data.anchor_count = impl->anchors.size();
  data.free_count = static_cast<std::size_t>(free_count);
  data.component_count = component_count;
  data.floating_components = impl->floating_parts.size();
  data.regularized_triangles = regularized;
  data.contacts_active = impl->contact_finder.has_value();
  data.impl = std::move(impl);
  data.precompute_seconds = SecondsSince(start);
}

double DeformationTransferData::Impl::Solve(std::span<const glm::vec3> expression,
                                           std::vector<glm::vec3>& out, Scratch& scratch) const {
  const std::size_t n = target_neutral.size();
  const Eigen::Index free_count = coupling.rows();
  scratch.contacts.clear();
  // Right-hand side U^T S, accumulated per vertex (x y z contiguous).
  scratch.desired.resize(triangles.size());
  scratch.accumulated.assign(3 * n, 0.0);
  double* acc = scratch.accumulated.data();
  for (std::size_t j = 0; j < triangles.size(); ++j) {
    const Mat32 desired = DesiredEdges(j, expression);
    scratch.desired[j] = desired;
    const Eigen::Matrix3d h = desired * triangle_data[j].rhs_operator;
    for (int a = 0; a < 3; ++a) {
      double* target = acc + 3 * static_cast<std::size_t>(triangles[j][static_cast<std::size_t>(a)]);
      target[0] += h(0, a);
      target[1] += h(1, a);
      target[2] += h(2, a);
    }
  }
  out.resize(n);
  if (still_fraction > 0.0) {
    SolveStillPinned(expression, acc, out, scratch);
    return Residual(out, scratch);
  }
  const auto anchor_count = static_cast<Eigen::Index>(anchors.size());
  scratch.anchor_positions.resize(anchor_count, 3);
  for (Eigen::Index i = 0; i < anchor_count; ++i) {
    const glm::vec3 p = AnchorPosition(anchors[static_cast<std::size_t>(i)], expression);
    scratch.anchor_positions.row(i) << p.x, p.y, p.z;
  }
  if (free_count > 0) {
    scratch.rhs.resize(free_count, 3);
    for (std::size_t v = 0; v < n; ++v) {
      const std::int32_t f = free_index[v];
      if (f < 0) continue;
      scratch.rhs.row(f) << acc[3 * v], acc[3 * v + 1], acc[3 * v + 2];
      if (prior > 0.0) {
        const glm::vec3 p = AnchorPosition(static_cast<std::uint32_t>(v), expression);
        scratch.rhs.row(f) += prior * Eigen::RowVector3d(p.x, p.y, p.z);
      }
    }
    scratch.rhs -= coupling * scratch.anchor_positions;
    scratch.solution = solver.solve(scratch.rhs);
    for (std::size_t v = 0; v < n; ++v) {
      const std::int32_t f = free_index[v];
      if (f < 0) continue;
      out[v] = glm::vec3(static_cast<float>(scratch.solution(f, 0)),
                         static_cast<float>(scratch.solution(f, 1)),
                         static_cast<float>(scratch.solution(f, 2)));
    }
  }
  for (Eigen::Index i = 0; i < anchor_count; ++i) {
    out[anchors[static_cast<std::size_t>(i)]] =
        glm::vec3(static_cast<float>(scratch.anchor_positions(i, 0)),
                  static_cast<float>(scratch.anchor_positions(i, 1)),
                  static_cast<float>(scratch.anchor_positions(i, 2)));
  }
  for (const std::vector<std::uint32_t>& part : floating_parts) {
    PlaceFloatingPart(part, expression, out);
  }
  return Residual(out, scratch);
}

void DeformationTransferData::Impl::SolveStillPinned(std::span<const glm::vec3> expression,
                                                     const double* accumulated,
                                                     std::vector<glm::vec3>& out,
                                                     Scratch& scratch) const {
  const std::size_t n = target_neutral.size();
  // Pinned: the static anchors and whatever this expression leaves still.
  float largest2 = 0.0f;
  for (std::size_t v = 0; v < n; ++v) {
    const glm::vec3 d = expression[v] - source_neutral[v];
    largest2 = std::max(largest2, d.x * d.x + d.y * d.y + d.z * d.z);
  }
  const auto still2 = static_cast<float>(still_fraction * still_fraction) * largest2;
  scratch.pinned.resize(n);
  for (std::size_t v = 0; v < n; ++v) {
    const glm::vec3 d = expression[v] - source_neutral[v];
    scratch.pinned[v] = is_static_anchor[v] || d.x * d.x + d.y * d.y + d.z * d.z <= still2;
  }
  if (rigid_tolerance > 0.0) PinRigidMotions(expression, out, scratch);
  // A part with nothing pinned moves as a whole: pin its gauge, place it after the solve.
  scratch.floating_components.clear();
  for (std::size_t c = 0; c < component_members.size(); ++c) {
    const std::vector<std::uint32_t>& part = component_members[c];
    if (std::none_of(part.begin(), part.end(), [&](std::uint32_t v) { return scratch.pinned[v]; })) {
      scratch.pinned[component_gauge[c]] = 1;
      scratch.floating_components.push_back(static_cast<std::uint32_t>(c));
    }
  }
  scratch.free_index.assign(n, -1);
  std::int32_t free_count = 0;
  for (std::size_t v = 0; v < n; ++v) {
    if (scratch.pinned[v] == kPinnedRigid) {
      continue;  // placed by PinRigidMotions
    } else if (scratch.pinned[v]) {
      out[v] = AnchorPosition(static_cast<std::uint32_t>(v), expression);
    } else {
      scratch.free_index[v] = free_count++;
    }
  }
  if (free_count > 0) {
    // The free rows of the whole system: free columns form the matrix, pinned
    // columns move to the right-hand side.
    scratch.rhs.resize(free_count, 3);
    for (std::size_t v = 0; v < n; ++v) {
      const std::int32_t f = scratch.free_index[v];
      if (f < 0) continue;
      scratch.rhs.row(f) << accumulated[3 * v], accumulated[3 * v + 1], accumulated[3 * v + 2];
      if (prior > 0.0) {
        const glm::vec3 p = AnchorPosition(static_cast<std::uint32_t>(v), expression);
        scratch.rhs.row(f) += prior * Eigen::RowVector3d(p.x, p.y, p.z);
      }
    }
    scratch.triplets.clear();
    for (Eigen::Index column = 0; column < full_system.outerSize(); ++column) {
      const std::int32_t free_column = scratch.free_index[static_cast<std::size_t>(column)];
      const glm::vec3 p = out[static_cast<std::size_t>(column)];
      for (Eigen::SparseMatrix<double>::InnerIterator it(full_system, column); it; ++it) {
        const std::int32_t free_row = scratch.free_index[static_cast<std::size_t>(it.row())];
        if (free_row < 0) continue;
        if (free_column >= 0) {
          scratch.triplets.emplace_back(free_row, free_column, it.value());
        } else {
          scratch.rhs.row(free_row) -= it.value() * Eigen::RowVector3d(p.x, p.y, p.z);
        }
      }
    }
    if (prior > 0.0) {
      for (std::int32_t f = 0; f < free_count; ++f) scratch.triplets.emplace_back(f, f, prior);
    }
    // Contacts: w |x_moving - x_partner - offset|^2, a pinned end on the right-hand
    // side; offset 0 when they close.
    if (contact_finder) {
      contact_finder->Find(expression, std::sqrt(largest2), scratch.free_index, scratch.contacts,
                           scratch.contact_scratch);
    }
    for (const ExpressionContact& contact : scratch.contacts) {
      const std::int32_t a = scratch.free_index[contact.moving];  // free: Find's moving ends are
      const std::int32_t b = scratch.free_index[contact.partner];
      const glm::vec3 offset =
          close_contacts ? glm::vec3(0.0f) : static_cast<float>(displacement_scale) * contact.offset;
      const Eigen::RowVector3d weighted_offset = contact_weight * Eigen::RowVector3d(offset.x, offset.y, offset.z);
      scratch.triplets.emplace_back(a, a, contact_weight);
      scratch.rhs.row(a) += weighted_offset;
      if (b >= 0) {
        scratch.triplets.emplace_back(b, b, contact_weight);
        scratch.triplets.emplace_back(a, b, -contact_weight);
        scratch.triplets.emplace_back(b, a, -contact_weight);
        scratch.rhs.row(b) -= weighted_offset;
      } else {
        const glm::vec3 p = out[contact.partner];  // pinned, placed above
        scratch.rhs.row(a) += contact_weight * Eigen::RowVector3d(p.x, p.y, p.z);
      }
    }
    scratch.system.resize(free_count, free_count);
    scratch.system.setFromTriplets(scratch.triplets.begin(), scratch.triplets.end());
    scratch.solver.compute(scratch.system);
    if (scratch.solver.info() != Eigen::Success) {
      throw TransferSolverError("deformation transfer: the sparse Cholesky factorization of " +
                                std::to_string(free_count) + " unknowns failed");
    }
    scratch.solution = scratch.solver.solve(scratch.rhs);
    for (std::size_t v = 0; v < n; ++v) {
      const std::int32_t f = scratch.free_index[v];
      if (f < 0) continue;
      out[v] = glm::vec3(static_cast<float>(scratch.solution(f, 0)),
                         static_cast<float>(scratch.solution(f, 1)),
                         static_cast<float>(scratch.solution(f, 2)));
    }
  }
  for (std::uint32_t c : scratch.floating_components) {
    PlaceFloatingPart(component_members[c], expression, out);
  }
}

void DeformationTransferData::Impl::PinRigidMotions(std::span<const glm::vec3> expression,
                                                    std::vector<glm::vec3>& out,
                                                    Scratch& scratch) const {
  // Sum of |R x + t - x'|^2 and of |x' - x|^2 over vertices (x rest, x' moved).
  auto fit_error = [&](const Eigen::Matrix4d& fit, std::span<const std::uint32_t> vertices) {
    double residual2 = 0.0;
    double motion2 = 0.0;
    for (std::uint32_t v : vertices) {
      const Eigen::Vector3d rest = ToEigen(source_neutral[v]);
      const Eigen::Vector3d moved = ToEigen(expression[v]);
      residual2 += (fit.topLeftCorner<3, 3>() * rest + fit.topRightCorner<3, 1>() - moved).squaredNorm();
      motion2 += (moved - rest).squaredNorm();
    }
    return std::pair{residual2, motion2};
  };
  const double tolerance2 = rigid_tolerance * rigid_tolerance;
  // Each part's moving vertices that the template moves as one rigid body.
  scratch.rigid_fits.clear();
  for (const std::vector<std::uint32_t>& part : component_members) {
    scratch.moving.clear();
    for (std::uint32_t v : part) {
      if (!scratch.pinned[v]) scratch.moving.push_back(v);
    }
    if (scratch.moving.size() < 4) continue;
    const auto count = static_cast<Eigen::Index>(scratch.moving.size());
    Eigen::Matrix3Xd rest(3, count);
    Eigen::Matrix3Xd moved(3, count);
    for (Eigen::Index i = 0; i < count; ++i) {
      const std::uint32_t v = scratch.moving[static_cast<std::size_t>(i)];
      rest.col(i) = ToEigen(source_neutral[v]);
      moved.col(i) = ToEigen(expression[v]);
    }
    const Eigen::Matrix4d fit = Eigen::umeyama(rest, moved, false);
    const auto [residual2, motion2] = fit_error(fit, scratch.moving);
    if (fit.allFinite() && motion2 > 0.0 && residual2 <= tolerance2 * motion2) {
      scratch.rigid_fits.push_back({fit, scratch.moving, scratch.rigid_fits.size()});
    }
  }
  // Parts that move by the same rigid motion (ICT: lower teeth, gums and
  // tongue with the jaw) move together, so they keep their places relative
  // to each other on the target.
  std::vector<Scratch::RigidFit>& fits = scratch.rigid_fits;
  for (std::size_t i = 0; i < fits.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (fits[j].group != j) continue;
      const auto [residual2, motion2] = fit_error(fits[j].transform, fits[i].vertices);
      if (residual2 <= tolerance2 * motion2) {
        fits[i].group = j;
        break;
      }
    }
  }
  // Each group: the template's rotation about the group's centroid on the
  // target, and the template's mean displacement.
  for (std::size_t g = 0; g < fits.size(); ++g) {
    if (fits[g].group != g) continue;
    Eigen::Vector3d target_centroid = Eigen::Vector3d::Zero();
    Eigen::Vector3d displacement = Eigen::Vector3d::Zero();
    std::size_t count = 0;
    for (const Scratch::RigidFit& fit : fits) {
      if (fit.group != g) continue;
      for (std::uint32_t v : fit.vertices) {
        target_centroid += ToEigen(target_neutral[v]);
        displacement += ToEigen(expression[v]) - ToEigen(source_neutral[v]);
      }
      count += fit.vertices.size();
    }
    target_centroid /= static_cast<double>(count);
    const Eigen::Vector3d shift =
        target_centroid + displacement_scale * displacement / static_cast<double>(count);
    const Eigen::Matrix3d rotation = fits[g].transform.topLeftCorner<3, 3>();
    for (const Scratch::RigidFit& fit : fits) {
      if (fit.group != g) continue;
      for (std::uint32_t v : fit.vertices) {
        const Eigen::Vector3d p = rotation * (ToEigen(target_neutral[v]) - target_centroid) + shift;
        out[v] = glm::vec3(static_cast<float>(p.x()), static_cast<float>(p.y()),
                           static_cast<float>(p.z()));
        scratch.pinned[v] = kPinnedRigid;
      }
    }
  }
}

void DeformationTransferData::Impl::PlaceFloatingPart(std::span<const std::uint32_t> part,
                                                      std::span<const glm::vec3> expression,
                                                      std::vector<glm::vec3>& out) const {
  // Exact least-squares optimum: a free part's gradient energy does not depend
  // on its translation.
  glm::dvec3 current(0.0);
  glm::dvec3 wanted(0.0);
  for (std::uint32_t v : part) {
    current += glm::dvec3(out[v]) - glm::dvec3(target_neutral[v]);
    wanted += glm::dvec3(expression[v]) - glm::dvec3(source_neutral[v]);
  }
  const glm::vec3 shift((wanted * displacement_scale - current) / static_cast<double>(part.size()));
  for (std::uint32_t v : part) out[v] += shift;
}

double DeformationTransferData::Impl::Residual(std::span<const glm::vec3> out,
                                               const Scratch& scratch) const {
  // sqrt(sum_j w_j |(E(X) - D) W|_F^2 / sum_j w_j), with w W W^T =
  // rhs_operator's right 2x2 block (B = [-1 1 0; -1 0 1]).
  double energy = 0.0;
  for (std::size_t j = 0; j < triangles.size(); ++j) {
    const Mat32 diff = Edges(out, triangles[j]) - scratch.desired[j];
    const Eigen::Matrix2d weighted_metric = triangle_data[j].rhs_operator.rightCols<2>();
    energy += (diff * weighted_metric * diff.transpose()).trace();
  }
  return std::sqrt(std::max(0.0, energy) / total_weight);
}

double SolveDeformationTransfer(const DeformationTransferData& data,
                                std::span<const glm::vec3> source_expression,
                                std::vector<glm::vec3>& target_expression) {
  if (!data.impl) throw TransferInputError("data", "not precomputed");
  CheckPositions(source_expression, data.vertex_count, "source expression");
  DeformationTransferData::Impl::Scratch scratch;
  const double residual = data.impl->Solve(source_expression, target_expression, scratch);
  return residual;
}

DeformationTransferResult DeformationTransfer(
    std::span<const glm::vec3> source_neutral, std::span<const glm::vec3> target_neutral,
    std::span<const Triangle> triangles, std::span<const std::vector<glm::vec3>> source_expressions,
    const DeformationTransferParams& params) {
  if (params.threads < 1) throw TransferInputError("params", "threads must be >= 1");
  DeformationTransferData data;
  PrecomputeDeformationTransfer(source_neutral, target_neutral, triangles, source_expressions,
                                params, data);
  DeformationTransferResult result;
  result.anchor_count = data.anchor_count;
  result.floating_components = data.floating_components;
  result.regularized_triangles = data.regularized_triangles;
  result.contacts_active = data.contacts_active;
  result.precompute_seconds = data.precompute_seconds;
  result.factorize_seconds = data.factorize_seconds;

  const Clock::time_point start = Clock::now();
  const std::size_t count = source_expressions.size();
  result.expressions.resize(count);
  result.residuals.assign(count, 0.0);
  result.contact_counts.assign(count, 0);
  const std::size_t threads = std::min<std::size_t>(static_cast<std::size_t>(params.threads),
                                                    std::max<std::size_t>(count, 1));
  const DeformationTransferData::Impl& impl = *data.impl;
  std::vector<std::exception_ptr> failures(threads);
  // Each expression goes to the next free thread (their costs differ: the
  // jaw's solve is the largest); each is solved on its own, so the results
  // do not depend on the split.
  std::atomic<std::size_t> next{0};
  auto run = [&](std::size_t t) {
    try {
      DeformationTransferData::Impl::Scratch scratch;
      for (std::size_t k = next++; k < count; k = next++) {
        result.residuals[k] = impl.Solve(source_expressions[k], result.expressions[k], scratch);
        result.contact_counts[k] = scratch.contacts.size();
      }
    } catch (...) {
      failures[t] = std::current_exception();  // rethrown on the calling thread
    }
  };
  std::vector<std::thread> workers;
  for (std::size_t t = 1; t < threads; ++t) workers.emplace_back(run, t);
  run(0);
  for (std::thread& worker : workers) worker.join();
  for (const std::exception_ptr& failure : failures) {
    if (failure) std::rethrow_exception(failure);
  }
  result.solve_seconds = SecondsSince(start);
  return result;
}

std::vector<std::vector<glm::vec3>> RigExpressionMeshes(const Rig& rig) {
  std::vector<std::vector<glm::vec3>> meshes(rig.shape_count());
  const std::span<const glm::vec3> neutral = rig.positions();
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    meshes[s].assign(neutral.begin(), neutral.end());
    const BlendShapeView shape = rig.shape(s);
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      meshes[s][shape.vertex_indices[i]] += shape.position_deltas[i];
    }
  }
  return meshes;
}

std::vector<RawBlendShape> MakeBlendShapes(std::span<const std::string> names,
                                           std::span<const glm::vec3> neutral,
                                           std::span<const std::vector<glm::vec3>> expressions,
                                           float relative_drop_threshold) {
  if (names.size() != expressions.size()) {
    throw TransferInputError("shape names", std::to_string(names.size()) + " names for " +
                                                std::to_string(expressions.size()) + " expressions");
  }
  const float threshold = relative_drop_threshold * BoundingDiagonal(neutral);
  std::vector<RawBlendShape> shapes;
  shapes.reserve(expressions.size());
  std::vector<glm::vec3> deltas(neutral.size());
  for (std::size_t s = 0; s < expressions.size(); ++s) {
    CheckPositions(expressions[s], neutral.size(), "expression '" + names[s] + "'");
    for (std::size_t v = 0; v < neutral.size(); ++v) deltas[v] = expressions[s][v] - neutral[v];
    shapes.push_back(MakeSparseShape(names[s], deltas, {}, threshold));
  }
  return shapes;
}

RawRig TransferRig(const Rig& template_rig, std::span<const glm::vec3> target_neutral,
                   const DeformationTransferParams& params, DeformationTransferResult* result) {
  CheckPositions(target_neutral, template_rig.vertex_count(), "target neutral");
  const std::vector<std::vector<glm::vec3>> expressions = RigExpressionMeshes(template_rig);
  DeformationTransferResult transfer = DeformationTransfer(
      template_rig.positions(), target_neutral, template_rig.triangles(), expressions, params);
  RawRig raw = RigBuilder::ToRaw(template_rig);
  raw.positions.assign(target_neutral.begin(), target_neutral.end());
  raw.normals.clear();
  std::vector<std::string> names;
  for (std::size_t s = 0; s < template_rig.shape_count(); ++s) {
    names.emplace_back(template_rig.shape_name(s));
  }
  raw.shapes = MakeBlendShapes(names, target_neutral, transfer.expressions);
  if (template_rig.has_normal_deltas()) {
    // Keep the rig's kind: normal deltas from the transferred meshes.
    std::vector<glm::vec3> neutral_normals(target_neutral.size());
    std::vector<glm::vec3> normals(target_neutral.size());
    ComputeVertexNormals(target_neutral, raw.triangles, neutral_normals);
    const float threshold = 1e-6f * BoundingDiagonal(target_neutral);
    std::vector<glm::vec3> deltas(target_neutral.size());
    for (std::size_t s = 0; s < raw.shapes.size(); ++s) {
      ComputeVertexNormals(transfer.expressions[s], raw.triangles, normals);
      for (std::size_t v = 0; v < normals.size(); ++v) {
        deltas[v] = transfer.expressions[s][v] - target_neutral[v];
        normals[v] -= neutral_normals[v];
      }
      raw.shapes[s] = MakeSparseShape(names[s], deltas, normals, threshold);
    }
  }
  if (result) *result = std::move(transfer);
  return raw;
}

}  // namespace facerig
