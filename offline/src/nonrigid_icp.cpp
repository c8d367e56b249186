#include "facerig/offline/nonrigid_icp.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#if defined(FACERIG_HAVE_CHOLMOD)
#include <Eigen/CholmodSupport>
#endif
#include <glm/geometric.hpp>

#include "facerig/offline/closest_point.h"
#include "facerig/offline/registration_error.h"
#include "facerig/offline/stats.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {
namespace {

using Clock = std::chrono::steady_clock;

glm::vec3 BoundsDiagonalVector(std::span<const glm::vec3> points, glm::vec3* lo_out = nullptr) {
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const glm::vec3& p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  if (lo_out != nullptr) *lo_out = lo;
  return hi - lo;
}

// Supernodal CHOLMOD when the build has it and the caller wants it (several
// times faster on the 4n x 4n system), else Eigen's simplicial LDL^T; the
// choice is at run time so a benchmark can run both. Both keep the symbolic
// analysis across factorizations.
class IcpSparseSolver {
 public:
  using Matrix = Eigen::SparseMatrix<double>;

  explicit IcpSparseSolver(bool prefer_cholmod) {
#if defined(FACERIG_HAVE_CHOLMOD)
    if (prefer_cholmod) {
      cholmod_.emplace();
      // Nested dissection (METIS) halves the factorization's flops against AMD
      // on this mesh-shaped pattern; trying every ordering costs seconds.
      cholmod_->cholmod().nmethods = 1;
      cholmod_->cholmod().method[0].ordering = CHOLMOD_METIS;
      return;
    }
#else
    (void)prefer_cholmod;
#endif
    simplicial_.emplace();
  }
  void AnalyzePattern(const Matrix& matrix) {
#if defined(FACERIG_HAVE_CHOLMOD)
    if (cholmod_) return cholmod_->analyzePattern(matrix);
#endif
    simplicial_->analyzePattern(matrix);
  }
  void Factorize(const Matrix& matrix) {
#if defined(FACERIG_HAVE_CHOLMOD)
    if (cholmod_) return cholmod_->factorize(matrix);
#endif
    simplicial_->factorize(matrix);
  }
  Eigen::MatrixXd Solve(const Eigen::MatrixXd& rhs) const {
#if defined(FACERIG_HAVE_CHOLMOD)
    if (cholmod_) return cholmod_->solve(rhs);
#endif
    return simplicial_->solve(rhs);
  }
  bool Ok() const {
#if defined(FACERIG_HAVE_CHOLMOD)
    if (cholmod_) return cholmod_->info() == Eigen::Success;
#endif
    return simplicial_->info() == Eigen::Success;
  }

 private:
#if defined(FACERIG_HAVE_CHOLMOD)
  std::optional<Eigen::CholmodSupernodalLLT<Matrix, Eigen::Lower>> cholmod_;
#endif
  std::optional<Eigen::SimplicialLDLT<Matrix, Eigen::Lower>> simplicial_;
};

// Per-vertex affine transform X_i (4 x 3, rows: linear part, then translation)
// applied to a point: X_i^T [p; 1].
glm::vec3 ApplyAffine(const Eigen::MatrixXd& x, std::size_t vertex, glm::vec3 p) {
  const auto row = static_cast<Eigen::Index>(4 * vertex);
  glm::vec3 out;
  for (int c = 0; c < 3; ++c) {
    out[c] = static_cast<float>(x(row, c) * p.x + x(row + 1, c) * p.y + x(row + 2, c) * p.z + x(row + 3, c));
  }
  return out;
}

}  // namespace

NonrigidIcpResult NonrigidIcp(const Mesh& template_mesh, const Mesh& target,
                              const RegistrationLandmarks& landmarks, const NonrigidIcpParams& params) {
  const auto start = Clock::now();
  CheckMesh(template_mesh, "non-rigid ICP template");
  CheckMesh(target, "non-rigid ICP target");
  const std::span<const glm::vec3> template_positions = template_mesh.positions;
  const std::span<const Triangle> template_triangles = template_mesh.triangles;
  if (params.stiffness.empty()) throw InvalidInputError("non-rigid ICP: the stiffness schedule is empty");
  const std::size_t landmark_count = landmarks.template_vertices.size();
  if (landmarks.target_points.size() != landmark_count ||
      (!landmarks.confidence.empty() && landmarks.confidence.size() != landmark_count)) {
    throw InvalidInputError("non-rigid ICP: landmark vertices, points and confidences differ in length");
  }
  for (std::size_t l = 0; l < landmark_count; ++l) {
    if (landmarks.template_vertices[l] >= template_positions.size()) {
      throw InvalidInputError("non-rigid ICP: landmark " + std::to_string(l) + " uses template vertex " +
                              std::to_string(landmarks.template_vertices[l]) + " of " +
                              std::to_string(template_positions.size()));
    }
    const glm::vec3 p = landmarks.target_points[l];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw InvalidInputError("non-rigid ICP: landmark " + std::to_string(l) + " is not finite");
    }
  }
  const std::size_t vertex_count = template_positions.size();
  const std::uint32_t region_limit = params.region_vertex_count == 0
                                         ? static_cast<std::uint32_t>(vertex_count)
                                         : std::min<std::uint32_t>(params.region_vertex_count,
                                                                   static_cast<std::uint32_t>(vertex_count));
  NonrigidIcpResult result;

  // --- the registered region: triangles whose vertices are all in range ---
  std::vector<Triangle> region_triangles_global;
  for (const Triangle& t : template_triangles) {
    if (t[0] < region_limit && t[1] < region_limit && t[2] < region_limit) region_triangles_global.push_back(t);
  }
  if (region_triangles_global.empty()) throw InvalidInputError("non-rigid ICP: the template region has no triangles");
  constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::uint32_t> local_of(vertex_count, kNone);
  std::vector<std::uint32_t> global_of;
  for (const Triangle& t : region_triangles_global) {
    for (std::uint32_t v : t) {
      if (local_of[v] == kNone) {
        local_of[v] = static_cast<std::uint32_t>(global_of.size());
        global_of.push_back(v);
      }
    }
  }
  const std::size_t n = global_of.size();
  std::vector<Triangle> region_triangles(region_triangles_global.size());
  for (std::size_t t = 0; t < region_triangles.size(); ++t) {
    for (std::size_t k = 0; k < 3; ++k) region_triangles[t][k] = local_of[region_triangles_global[t][k]];
  }

  // --- rigid pre-alignment (template -> target coordinates) ---
  const auto rigid_start = Clock::now();
  // One closest-point structure of the target, in its own coordinates, for
  // the rigid step and (queries mapped in and out of the working frame) the
  // non-rigid one: on a million-vertex scan a second copy cost ~2 s and
  // ~200 MB.
  const ClosestPointQuery target_world(target);
  // The similarity comes from the confident landmarks (dlib's jaw points
  // follow the silhouette) when at least 6 of them exist, else from all.
  std::vector<glm::vec3> source_landmarks, target_landmarks;
  for (const float min_confidence : {0.5f, 0.0f}) {
    source_landmarks.clear();
    target_landmarks.clear();
    for (std::size_t l = 0; l < landmark_count; ++l) {
      if (local_of[landmarks.template_vertices[l]] == kNone) continue;
      const float confidence = landmarks.confidence.empty() ? 1.0f : landmarks.confidence[l];
      if (!(confidence > 0.0f) || confidence < min_confidence) continue;
      source_landmarks.push_back(template_positions[landmarks.template_vertices[l]]);
      target_landmarks.push_back(landmarks.target_points[l]);
    }
    if (source_landmarks.size() >= 6) break;
  }
  if (params.rigid_prealign) {
    const bool use_landmarks = source_landmarks.size() >= 3;
    const RigidAlignResult rigid = RigidAlign(
        Mesh{.positions = template_mesh.positions, .triangles = region_triangles_global}, target_world,
        use_landmarks ? std::span<const glm::vec3>(source_landmarks) : std::span<const glm::vec3>(),
        use_landmarks ? std::span<const glm::vec3>(target_landmarks) : std::span<const glm::vec3>(),
        params.rigid, nullptr);
    result.rigid = rigid.transform;
    // Landmarks laid out unlike a face's (a grid on a sheet) can make the
    // best similarity shrink the template to a point.
    if (use_landmarks) {
      auto spread = [](std::span<const glm::vec3> points) {
        glm::vec3 centre(0.0f);
        for (const glm::vec3& p : points) centre += p / static_cast<float>(points.size());
        double sum = 0.0;
        for (const glm::vec3& p : points) sum += glm::dot(p - centre, p - centre);
        return std::sqrt(sum / static_cast<double>(points.size()));
      };
      const double expected_scale = spread(target_landmarks) / spread(source_landmarks);
      if (!(result.rigid.scale > 0.01 * expected_scale)) {
        throw InvalidInputError("non-rigid ICP: the landmarks do not match the template's: aligning them shrinks "
                                "the template to a point (scale " + std::to_string(result.rigid.scale) +
                                ", landmark residual " + std::to_string(rigid.landmark_rms) +
                                "); is the target a face, and are the landmarks right?");
      }
    }
  }
  result.timings.rigid_seconds = SecondsSince(rigid_start);

  // --- working frame: template region centred, diagonal = working_diagonal ---
  const auto setup_start = Clock::now();
  std::vector<glm::vec3> aligned(vertex_count);
  for (std::size_t v = 0; v < vertex_count; ++v) aligned[v] = result.rigid.Apply(template_positions[v]);
  std::vector<glm::vec3> region_aligned(n);
  for (std::size_t i = 0; i < n; ++i) region_aligned[i] = aligned[global_of[i]];
  glm::vec3 region_lo;
  const glm::vec3 region_extent = BoundsDiagonalVector(region_aligned, &region_lo);
  const glm::vec3 centre = region_lo + 0.5f * region_extent;
  const double region_diagonal = glm::length(region_extent);
  if (!(region_diagonal > 0.0)) throw InvalidInputError("non-rigid ICP: the template region is a single point");
  const auto to_work_scale = static_cast<float>(params.working_diagonal / region_diagonal);
  auto to_work = [&](glm::vec3 p) { return (p - centre) * to_work_scale; };
  auto to_world = [&](glm::vec3 p) { return p / to_work_scale + centre; };

  // Nearest target surface point of a working-frame point (working frame in and out).
  auto find_target = [&](glm::vec3 p, float max_distance) {
    ClosestPointHit hit = target_world.Find(to_world(p), max_distance / to_work_scale);
    if (hit.triangle >= 0) {
      hit.point = to_work(hit.point);
      hit.distance *= to_work_scale;
    }
    return hit;
  };
  // The target's size from the vertices its triangles use: a stray point far
  // away (scans have them) must not loosen the rejection distances or shrink
  // the residual percentages.
  std::vector<glm::vec3> surface_points;
  {
    std::vector<std::uint8_t> used(target.vertex_count(), 0);
    for (const Triangle& t : target.triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
    surface_points.reserve(target.vertex_count());
    for (std::size_t v = 0; v < target.vertex_count(); ++v) {
      if (used[v]) surface_points.push_back(target.positions[v]);
    }
  }
  result.residual.target_diagonal = glm::length(BoundsDiagonalVector(surface_points));
  const double target_diagonal_work = result.residual.target_diagonal * static_cast<double>(to_work_scale);
  surface_points = {};

  std::vector<glm::vec3> rest(n);  // undeformed template region, working frame
  for (std::size_t i = 0; i < n; ++i) rest[i] = to_work(region_aligned[i]);

  // Landmarks in the region (local index, working-frame target, weight factor).
  struct LocalLandmark {
    std::uint32_t vertex;
    glm::vec3 target;
    double confidence;
  };
  std::vector<LocalLandmark> local_landmarks;
  for (std::size_t l = 0; l < landmark_count; ++l) {
    const std::uint32_t local = local_of[landmarks.template_vertices[l]];
    const double confidence = landmarks.confidence.empty() ? 1.0 : static_cast<double>(landmarks.confidence[l]);
    if (local == kNone || !(confidence > 0.0)) continue;
    local_landmarks.push_back({local, to_work(landmarks.target_points[l]), confidence});
  }

  // Unique undirected edges of the region (the stiffness term's node-arc incidence).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  edges.reserve(region_triangles.size() * 3);
  for (const Triangle& t : region_triangles) {
    for (std::size_t e = 0; e < 3; ++e) {
      const std::uint32_t a = t[e], b = t[(e + 1) % 3];
      if (a != b) edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());

  // The matrix pattern never changes: full 4x4 blocks on the diagonal (data
  // and landmark terms; explicit zeros where a correspondence is rejected)
  // plus the diagonal of each edge block (G is diagonal). Only the lower
  // triangle is stored (SimplicialLDLT reads the lower part).
  const auto unknowns = static_cast<Eigen::Index>(4 * n);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(10 * n + 4 * edges.size());
  std::vector<double> edge_count(n, 0.0);
  for (const auto& [a, b] : edges) {
    edge_count[a] += 1.0;
    edge_count[b] += 1.0;
  }
  const double gamma2 = params.gamma * params.gamma;
  // Fills `matrix` (pattern fixed) for stiffness alpha and the given per-vertex
  // data weights; the landmark term is added by the caller through `diag_blocks`.
  std::vector<Eigen::Matrix4d> diag_blocks(n);
  auto assemble = [&](double alpha) {
    triplets.clear();
    const double a2 = alpha * alpha;
    for (std::size_t i = 0; i < n; ++i) {
      Eigen::Matrix4d block = diag_blocks[i];
      for (int k = 0; k < 4; ++k) block(k, k) += a2 * edge_count[i] * (k == 3 ? gamma2 : 1.0);
      for (int r = 0; r < 4; ++r) {
        for (int c = 0; c <= r; ++c) {
          triplets.emplace_back(static_cast<Eigen::Index>(4 * i) + r, static_cast<Eigen::Index>(4 * i) + c,
                                block(r, c));
        }
      }
    }
    for (const auto& [a, b] : edges) {
      for (int k = 0; k < 4; ++k) {
        // Row index larger than column: lower triangle (b > a).
        triplets.emplace_back(static_cast<Eigen::Index>(4 * b) + k, static_cast<Eigen::Index>(4 * a) + k,
                              -a2 * (k == 3 ? gamma2 : 1.0));
      }
    }
  };

  Eigen::SparseMatrix<double> matrix(unknowns, unknowns);
  IcpSparseSolver solver(params.use_cholmod);
  for (auto& block : diag_blocks) block.setIdentity();
  assemble(1.0);
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  solver.AnalyzePattern(matrix);  // once: every later matrix has this pattern
  result.timings.setup_seconds = SecondsSince(setup_start);

  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(unknowns, 3);  // identity transforms
  for (std::size_t i = 0; i < n; ++i) x.block<3, 3>(static_cast<Eigen::Index>(4 * i), 0).setIdentity();
  Eigen::MatrixXd rhs(unknowns, 3);
  std::vector<glm::vec3> deformed(rest), normals(n);
  std::vector<ClosestPointHit> hits(n);
  std::vector<std::uint8_t> accepted(n, 0), weighted(n, 0);
  std::vector<double> distances;
  const double cos_limit = std::cos(params.max_normal_angle_degrees * 3.14159265358979323846 / 180.0);
  constexpr double kRidge = 1e-6;  // keeps parts without any data term solvable

  // Closest points of the deformed template with rejection; fills hits/accepted.
  auto find_correspondences = [&]() {
    const auto t0 = Clock::now();
    ComputeVertexNormals(deformed, region_triangles, normals);
    const auto far_limit = static_cast<float>(params.max_reject_distance * target_diagonal_work);
    distances.clear();
    for (std::size_t i = 0; i < n; ++i) {
      hits[i] = find_target(deformed[i], far_limit);
      const bool ok = hits[i].triangle >= 0 && !(params.reject_boundary && hits[i].on_boundary) &&
                      glm::dot(normals[i], hits[i].normal) >= cos_limit;
      accepted[i] = ok ? 1 : 0;
      if (ok) distances.push_back(hits[i].distance);
    }
    const double median = Percentile(distances, 0.5);
    const double limit = std::max(params.distance_median_factor * median,
                                  params.min_reject_distance * target_diagonal_work);
    for (std::size_t i = 0; i < n; ++i) {
      if (accepted[i] && hits[i].distance > limit) accepted[i] = 0;
    }
    result.timings.correspondence_seconds += SecondsSince(t0);
  };

  for (std::size_t stage = 0; stage < params.stiffness.size(); ++stage) {
    const double alpha = params.stiffness[stage];
    const double beta = params.landmark_weights.empty()
                            ? 0.0
                            : params.landmark_weights[std::min(stage, params.landmark_weights.size() - 1)];
    int iterations = 0;
    for (int iteration = 0; iteration < params.max_iterations_per_stage; ++iteration) {
      find_correspondences();
      // The matrix depends only on the stiffness, the landmark weight and
      // which vertices have a data term (not where their correspondences
      // land). The set is fixed at each stage's first iteration, so a stage
      // costs one numeric factorization; later iterations only back-solve.
      // A vertex that loses its correspondence within the stage is pulled
      // to where it is (no force) rather than dropped from the matrix.
      if (iteration == 0) weighted = accepted;
      rhs.setZero();
      for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector4d d(rest[i].x, rest[i].y, rest[i].z, 1.0);
        Eigen::Matrix4d& block = diag_blocks[i];
        block = kRidge * Eigen::Matrix4d::Identity();
        const auto row = static_cast<Eigen::Index>(4 * i);
        rhs.block<3, 3>(row, 0) += kRidge * Eigen::Matrix3d::Identity();
        if (weighted[i]) {
          block += d * d.transpose();
          const glm::vec3 goal = accepted[i] ? hits[i].point : deformed[i];
          const Eigen::RowVector3d u(goal.x, goal.y, goal.z);
          rhs.block<4, 3>(row, 0) += d * u;
        }
      }
      for (const LocalLandmark& landmark : local_landmarks) {
        const glm::vec3 p = rest[landmark.vertex];
        const Eigen::Vector4d d(p.x, p.y, p.z, 1.0);
        const double w = beta * beta * landmark.confidence;
        diag_blocks[landmark.vertex] += w * d * d.transpose();
        const Eigen::RowVector3d u(landmark.target.x, landmark.target.y, landmark.target.z);
        rhs.block<4, 3>(static_cast<Eigen::Index>(4 * landmark.vertex), 0) += w * d * u;
      }
      Eigen::MatrixXd next;
      if (iteration == 0) {
        assemble(alpha);
        matrix.setFromTriplets(triplets.begin(), triplets.end());
        const auto t0 = Clock::now();
        solver.Factorize(matrix);
        ++result.factorizations;
        result.timings.factorize_seconds += SecondsSince(t0);
        if (!solver.Ok()) {
          throw SolverError("non-rigid ICP: factorization failed at stiffness " + std::to_string(alpha));
        }
      }
      const auto t0 = Clock::now();
      next = solver.Solve(rhs);
      result.timings.solve_seconds += SecondsSince(t0);
      if (!solver.Ok() || !next.allFinite()) {
        throw SolverError("non-rigid ICP: the solve failed at stiffness " + std::to_string(alpha));
      }
      x.swap(next);
      double moved = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3 p = ApplyAffine(x, i, rest[i]);
        moved += glm::length(p - deformed[i]);
        deformed[i] = p;
      }
      ++iterations;
      if (moved / static_cast<double>(n) < params.convergence * params.working_diagonal) break;
    }
    result.iterations_per_stage.push_back(iterations);
    if (params.progress) params.progress(stage + 1, params.stiffness.size());
  }

  // --- final correspondences and residuals ---
  find_correspondences();
  result.positions.assign(vertex_count, glm::vec3(0.0f));
  result.correspondence.assign(vertex_count, SurfaceCorrespondence{});
  std::vector<double> residuals;
  residuals.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t v = global_of[i];
    result.positions[v] = to_world(deformed[i]);
    if (accepted[i]) {
      result.correspondence[v] = {hits[i].triangle, hits[i].barycentrics};
      residuals.push_back(static_cast<double>(hits[i].distance) / target_diagonal_work * 100.0);
    } else {
      ++result.residual.rejected_count;
    }
  }
  if (!residuals.empty()) {
    double sum = 0.0, max = 0.0;
    for (double r : residuals) {
      sum += r;
      max = std::max(max, r);
    }
    result.residual.mean_percent = sum / static_cast<double>(residuals.size());
    result.residual.max_percent = max;
    result.residual.p95_percent = Percentile(residuals, 0.95);
  }
  result.residual.vertex_count = residuals.size();

  // --- inner parts: each vertex takes the affine transforms of its nearest
  // point on the undeformed region surface (barycentric blend), so eyeballs,
  // teeth and the mouth socket move with the skin around them ---
  std::vector<std::uint32_t> inner;
  for (std::uint32_t v = 0; v < vertex_count; ++v) {
    if (local_of[v] == kNone) inner.push_back(v);
  }
  if (!inner.empty()) {
    const ClosestPointQuery rest_surface(Mesh{.positions = {rest.begin(), rest.end()}, .triangles = region_triangles});
    for (std::uint32_t v : inner) {
      const glm::vec3 p = to_work(aligned[v]);
      const ClosestPointHit hit = rest_surface.Find(p);
      const Triangle& t = region_triangles[static_cast<std::size_t>(hit.triangle)];
      glm::vec3 moved(0.0f);
      for (int k = 0; k < 3; ++k) moved += hit.barycentrics[k] * ApplyAffine(x, t[static_cast<std::size_t>(k)], p);
      result.positions[v] = to_world(moved);
    }
  }

  if (!local_landmarks.empty()) {
    double sum = 0.0;
    for (const LocalLandmark& landmark : local_landmarks) {
      const glm::vec3 d = to_world(deformed[landmark.vertex]) - to_world(landmark.target);
      sum += static_cast<double>(glm::dot(d, d));
    }
    result.landmark_rms = std::sqrt(sum / static_cast<double>(local_landmarks.size()));
  }
  result.timings.total_seconds = SecondsSince(start);
  return result;
}

}  // namespace facerig
