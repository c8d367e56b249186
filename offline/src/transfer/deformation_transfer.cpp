#include "transfer/deformation_transfer_impl.h"

#include "facerig/offline/geometry/mesh_components.h"

#include <atomic>
#include <exception>
#include <numeric>
#include <thread>

namespace facerig {

const char* ToString(TransferMode mode) {
  switch (mode) {
    case TransferMode::kClassic: return "classic";
    case TransferMode::kIdentityGradient: return "identity";
  }
  return "unknown";
}

DeformationTransferData::DeformationTransferData() = default;
DeformationTransferData::~DeformationTransferData() = default;
DeformationTransferData::DeformationTransferData(DeformationTransferData&&) noexcept = default;
DeformationTransferData& DeformationTransferData::operator=(DeformationTransferData&&) noexcept =
    default;

namespace {

void ValidateTransferInputs(std::span<const glm::vec3> source_neutral, std::span<const glm::vec3> target_neutral,
                            std::span<const Triangle> triangles,
                            std::span<const std::vector<glm::vec3>> source_expressions,
                            const DeformationTransferParams& params) {
  const std::size_t n = source_neutral.size();
  if (n == 0 || triangles.empty()) {
    throw MeshInputError("source neutral", "needs vertices and triangles");
  }
  CheckPositions(source_neutral, n, "source neutral");
  CheckPositions(target_neutral, n, "target neutral");
  for (std::size_t k = 0; k < source_expressions.size(); ++k) {
    CheckPositions(source_expressions[k], n, "source expression " + std::to_string(k));
  }
  for (std::size_t j = 0; j < triangles.size(); ++j) {
    for (std::uint32_t v : triangles[j]) {
      if (v >= n) {
        throw MeshInputError("triangles", "triangle " + std::to_string(j) + " uses vertex " +
                                                  std::to_string(v) + " >= " + std::to_string(n));
      }
    }
  }
  if (!(params.displacement_scale > 0.0f) || !std::isfinite(params.displacement_scale)) {
    throw MeshInputError("params", "displacement_scale must be finite and > 0");
  }
  if (!(params.displacement_prior >= 0.0) || !std::isfinite(params.displacement_prior)) {
    throw MeshInputError("params", "displacement_prior must be finite and >= 0");
  }
  if (!(params.min_gram_ratio > 0.0) || !(params.min_gram_ratio < 1.0)) {
    throw MeshInputError("params", "min_gram_ratio must be in (0, 1)");
  }
  if (!(params.still_fraction >= 0.0) || !(params.still_fraction < 1.0)) {
    throw MeshInputError("params", "still_fraction must be in [0, 1)");
  }
  if (!(params.rigid_tolerance >= 0.0) || !(params.rigid_tolerance < 1.0)) {
    throw MeshInputError("params", "rigid_tolerance must be in [0, 1)");
  }
  if (!(params.contact_weight >= 0.0) || !std::isfinite(params.contact_weight)) {
    throw MeshInputError("params", "contact_weight must be finite and >= 0");
  }
}

// Anchored vertices: the given list, or the template's static set, plus vertices in no triangle.
std::vector<char> FindAnchors(std::span<const glm::vec3> source_neutral, std::span<const Triangle> triangles,
                              std::span<const std::vector<glm::vec3>> source_expressions,
                              const DeformationTransferParams& params) {
  const std::size_t n = source_neutral.size();
  std::vector<char> is_anchor(n, 0);
  if (!params.anchor_vertices.empty()) {
    for (std::uint32_t v : params.anchor_vertices) {
      if (v >= n) {
        throw MeshInputError("anchor vertices", "vertex " + std::to_string(v) + " >= " +
                                                        std::to_string(n));
      }
      is_anchor[v] = 1;
    }
  } else {
    if (source_expressions.empty()) {
      throw MeshInputError("source expressions",
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
  return is_anchor;
}

// Every connected part needs an anchor; parts without one get a gauge vertex
// (the one nearest the part's centroid) and are placed by mean displacement.
// Returns the number of parts; marks the gauges in is_anchor.
std::size_t AnchorEveryPart(std::span<const glm::vec3> target_neutral, std::span<const Triangle> triangles,
                            bool still_pinning, std::vector<char>& is_anchor, DeformationTransferData::Impl& impl) {
  const std::size_t n = target_neutral.size();
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
    impl.component_of_vertex = component;
    impl.component_members.resize(component_count);
    for (std::uint32_t v = 0; v < n; ++v) impl.component_members[component[v]].push_back(v);
    for (const std::vector<std::uint32_t>& part : impl.component_members) {
      impl.component_gauge.push_back(gauge_of(part));
    }
  }
  for (std::size_t c = 0; c < component_count; ++c) {
    if (anchored[c]) continue;
    is_anchor[gauge_of(members[c])] = 1;
    impl.floating_parts.push_back(std::move(members[c]));
  }

  return component_count;
}

// A triangle's frames (classic and identity-gradient) and its gradient metric
// (E^T E)^-1 from the target's edges; clamped: R's diagonal had to be bounded.
Eigen::Matrix2d PrepareTriangle(const Mat32& source_edges, double mean_edge2, const DeformationTransferParams& params,
                                DeformationTransferData::Impl::TriangleData& d, bool& clamped) {
  d.source_degenerate = GramRatio(source_edges) < params.min_gram_ratio;
  if (!d.source_degenerate) {
    d.source_frame_inverse = TriangleFrame(source_edges, params.scaled_normal).inverse();
    d.identity_gradient = TriangleFrame(d.target_edges, params.scaled_normal) * d.source_frame_inverse;
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
  if (std::abs(r(0, 0)) < r0_min) {
    r(0, 0) = r0_min;
    r(0, 1) = 0.0;
    clamped = true;
  }
  const double r1_min = std::max(std::sqrt(params.min_gram_ratio) * std::abs(r(0, 0)), r0_min);
  if (std::abs(r(1, 1)) < r1_min) {
    r(1, 1) = r(1, 1) < 0.0 ? -r1_min : r1_min;
    clamped = true;
  }
  const Mat32 q = qr.householderQ() * Mat32::Identity();
  const Mat23 w = r.inverse() * q.transpose();  // 2x3
  return w * w.transpose();  // (E^T E)^-1, regularized
}

// The normal equations U^T U as triplets: the whole #V x #V system (still
// pinning), or the free vertices' system and their coupling to the anchors.
struct NormalEquations {
  std::vector<Eigen::Triplet<double>> free;
  std::vector<Eigen::Triplet<double>> coupling;
  std::vector<Eigen::Triplet<double>> full;
  std::size_t regularized = 0;  // triangles clamped or with a degenerate source
};

// A triangle's 3x3 block of the normal equations. With still pinning, into
// the whole system (each expression restricts it to what it moves); without,
// into the free vertices' shared system and its coupling to the anchors.
void AddTriangleBlock(const Triangle& t, const Eigen::Matrix3d& local, std::span<const std::int32_t> free_index,
                      std::span<const std::int32_t> anchor_index, bool still_pinning,
                      NormalEquations& equations) {
  for (int row = 0; row < 3; ++row) {
    const std::uint32_t vr = t[static_cast<std::size_t>(row)];
    for (int col = 0; col < 3; ++col) {
      const std::uint32_t vc = t[static_cast<std::size_t>(col)];
      if (still_pinning) {
        equations.full.emplace_back(vr, vc, local(row, col));
      } else if (free_index[vr] >= 0) {
        if (free_index[vc] >= 0) {
          equations.free.emplace_back(free_index[vr], free_index[vc], local(row, col));
        } else {
          equations.coupling.emplace_back(free_index[vr], anchor_index[vc], local(row, col));
        }
      }
    }
  }
}

// The parameters and meshes the solves need, copied into a fresh Impl.
std::unique_ptr<DeformationTransferData::Impl> StartImpl(std::span<const glm::vec3> source_neutral,
                                                         std::span<const glm::vec3> target_neutral,
                                                         std::span<const Triangle> triangles,
                                                         const DeformationTransferParams& params) {
  auto impl = std::make_unique<DeformationTransferData::Impl>();
  impl->mode = params.mode;
  impl->scaled_normal = params.scaled_normal;
  impl->displacement_scale = params.displacement_scale;
  impl->still_fraction = params.still_fraction;
  impl->rigid_tolerance = params.rigid_tolerance;
  impl->triangles.assign(triangles.begin(), triangles.end());
  impl->source_neutral.assign(source_neutral.begin(), source_neutral.end());
  impl->target_neutral.assign(target_neutral.begin(), target_neutral.end());
  return impl;
}

// Numbers the anchors (impl.anchors, anchor_index) and the free vertices
// (impl.free_index) in vertex order; returns the number of free vertices.
std::int32_t IndexVertices(std::span<const char> is_anchor, DeformationTransferData::Impl& impl,
                           std::vector<std::int32_t>& anchor_index) {
  const std::size_t n = is_anchor.size();
  impl.free_index.assign(n, -1);
  anchor_index.assign(n, -1);
  std::int32_t free_count = 0;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (is_anchor[v]) {
      anchor_index[v] = static_cast<std::int32_t>(impl.anchors.size());
      impl.anchors.push_back(v);
    } else {
      impl.free_index[v] = free_count++;
    }
  }
  return free_count;
}

// The target's mean triangle area and mean squared edge length: the scales of
// the area weights and of the needle clamping.
struct TargetScale {
  double mean_area = 0.0;
  double mean_edge2 = 0.0;
};

TargetScale MeasureTarget(std::span<const glm::vec3> target_neutral, std::span<const Triangle> triangles) {
  TargetScale scale;
  for (const Triangle& t : triangles) {
    const Mat32 e = Edges(target_neutral, t);
    scale.mean_area += 0.5 * e.col(0).cross(e.col(1)).norm();
    scale.mean_edge2 += 0.5 * e.colwise().squaredNorm().sum();
  }
  scale.mean_area /= static_cast<double>(triangles.size());
  scale.mean_edge2 /= static_cast<double>(triangles.size());
  if (!(scale.mean_edge2 > 0.0)) throw MeshInputError("target neutral", "all triangles are points");
  return scale;
}

// Fills impl.triangle_data and impl.total_weight, and returns the triangles' blocks.
NormalEquations AssembleNormalEquations(std::span<const glm::vec3> source_neutral,
                                        std::span<const glm::vec3> target_neutral,
                                        std::span<const Triangle> triangles,
                                        std::span<const std::int32_t> anchor_index, bool still_pinning,
                                        const DeformationTransferParams& params,
                                        DeformationTransferData::Impl& impl) {
  const TargetScale scale = MeasureTarget(target_neutral, triangles);
  Mat23 b;  // edge operator: (e1, e2) = X * B^T over the triangle's 3 vertices
  b << -1.0, 1.0, 0.0, -1.0, 0.0, 1.0;
  NormalEquations equations;
  (still_pinning ? equations.full : equations.free).reserve(triangles.size() * 9);
  impl.triangle_data.resize(triangles.size());
  for (std::size_t j = 0; j < triangles.size(); ++j) {
    const Triangle& t = triangles[j];
    DeformationTransferData::Impl::TriangleData& d = impl.triangle_data[j];
    d.target_edges = Edges(target_neutral, t);
    const Mat32 source_edges = Edges(source_neutral, t);

    bool clamped = false;
    const Eigen::Matrix2d metric = PrepareTriangle(source_edges, scale.mean_edge2, params, d, clamped);
    if (clamped || d.source_degenerate) ++equations.regularized;
    double weight = 1.0;
    if (params.area_weighted) {
      const double area = 0.5 * d.target_edges.col(0).cross(d.target_edges.col(1)).norm();
      weight = std::max(area, 1e-3 * scale.mean_area) / scale.mean_area;
    }
    impl.total_weight += weight;
    d.rhs_operator = weight * metric * b;
    const Eigen::Matrix3d local = b.transpose() * d.rhs_operator;  // w B^T M B
    AddTriangleBlock(t, local, impl.free_index, anchor_index, still_pinning, equations);
  }
  return equations;
}

// Without still pinning: the free vertices' system shared by every expression
// (with the displacement prior on its diagonal) and impl.coupling to the anchors.
Eigen::SparseMatrix<double> BuildFreeSystem(const NormalEquations& equations, std::int32_t free_count,
                                            const DeformationTransferParams& params,
                                            DeformationTransferData::Impl& impl) {
  Eigen::SparseMatrix<double> system(free_count, free_count);
  system.setFromTriplets(equations.free.begin(), equations.free.end());
  if (params.displacement_prior > 0.0 && free_count > 0) {
    impl.prior = params.displacement_prior * system.diagonal().mean();
    for (std::int32_t f = 0; f < free_count; ++f) system.coeffRef(f, f) += impl.prior;
  }
  impl.coupling.resize(free_count, static_cast<Eigen::Index>(impl.anchors.size()));
  impl.coupling.setFromTriplets(equations.coupling.begin(), equations.coupling.end());
  return system;
}

// Still pinning: the whole system that each expression restricts to its own
// free vertices, the prior and contact weights relative to its diagonal, and
// the contact finder.
void SetUpStillPinning(const NormalEquations& equations, const DeformationTransferParams& params,
                       DeformationTransferData::Impl& impl) {
  const auto n = static_cast<Eigen::Index>(impl.target_neutral.size());
  impl.full_system.resize(n, n);
  impl.full_system.setFromTriplets(equations.full.begin(), equations.full.end());
  if (params.displacement_prior > 0.0) {
    impl.prior = params.displacement_prior * impl.full_system.diagonal().mean();
  }
  if (params.contact_weight > 0.0) {
    impl.contact_weight = params.contact_weight * impl.full_system.diagonal().mean();
    impl.close_contacts = params.close_contacts;
    impl.contact_finder.emplace(impl.source_neutral, impl.triangles, impl.component_of_vertex, params.openings);
  }
}

void Factorize(const Eigen::SparseMatrix<double>& system, DeformationTransferData::Impl& impl) {
  impl.solver.compute(system);
  if (impl.solver.info() != Eigen::Success) {
    throw TransferSolverError("deformation transfer: the sparse Cholesky factorization of " +
                              std::to_string(system.rows()) + " unknowns failed");
  }
}

}  // namespace

void PrecomputeDeformationTransfer(const Mesh& source, std::span<const glm::vec3> target_neutral,
                                   std::span<const std::vector<glm::vec3>> source_expressions,
                                   const DeformationTransferParams& params,
                                   DeformationTransferData& data) {
  const Clock::time_point start = Clock::now();
  const std::span<const glm::vec3> source_neutral = source.positions;
  const std::span<const Triangle> triangles = source.triangles;
  ValidateTransferInputs(source_neutral, target_neutral, triangles, source_expressions, params);
  auto impl = StartImpl(source_neutral, target_neutral, triangles, params);

  std::vector<char> is_anchor = FindAnchors(source_neutral, triangles, source_expressions, params);
  const bool still_pinning = params.still_fraction > 0.0;
  if (still_pinning) impl->is_static_anchor = is_anchor;
  const std::size_t component_count = AnchorEveryPart(target_neutral, triangles, still_pinning, is_anchor, *impl);
  std::vector<std::int32_t> anchor_index;
  const std::int32_t free_count = IndexVertices(is_anchor, *impl, anchor_index);

  const NormalEquations equations = AssembleNormalEquations(source_neutral, target_neutral, triangles,
                                                            anchor_index, still_pinning, params, *impl);
  if (still_pinning) {
    // Each expression factorizes its own system (SolveDeformationTransfer).
    SetUpStillPinning(equations, params, *impl);
  } else {
    const Eigen::SparseMatrix<double> system = BuildFreeSystem(equations, free_count, params, *impl);
    const Clock::time_point factorize_start = Clock::now();
    if (free_count > 0) Factorize(system, *impl);
    data.factorize_seconds = SecondsSince(factorize_start);
  }

  data.vertex_count = source_neutral.size();
  data.triangle_count = triangles.size();
  data.anchor_count = impl->anchors.size();
  data.free_count = static_cast<std::size_t>(free_count);
  data.component_count = component_count;
  data.floating_components = impl->floating_parts.size();
  data.regularized_triangles = equations.regularized;
  data.contacts_active = impl->contact_finder.has_value();
  data.impl = std::move(impl);
  data.precompute_seconds = SecondsSince(start);
}

}  // namespace facerig
