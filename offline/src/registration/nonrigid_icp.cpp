// The entry point of non-rigid ICP and its stiffness schedule: the sparse
// normal equations, their factorization and the ICP iterations. The stages
// around the solve are in nonrigid_icp_region.cpp.
#include "facerig/offline/registration/nonrigid_icp.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <span>
#include <string>
#include <utility>

#include <Eigen/Sparse>
#include <glm/geometric.hpp>

#include "facerig/offline/geometry/closest_point.h"
#include "facerig/offline/error.h"
#include "facerig/offline/geometry/stats.h"
#include "facerig/runtime/rig_builder.h"
#include "registration/icp_sparse_solver.h"
#include "geometry/parallel_for.h"
#include "registration/nonrigid_icp_impl.h"

namespace facerig {
namespace {

using nonrigid_icp_detail::ApplyAffine;
using nonrigid_icp_detail::IcpFit;
using nonrigid_icp_detail::IcpProblem;
using nonrigid_icp_detail::IcpRegion;
using nonrigid_icp_detail::LocalLandmark;
using Clock = std::chrono::steady_clock;

using Edge = IcpSparseSolver::Edge;

// Unique undirected edges of the region (the stiffness term's node-arc incidence).
std::vector<Edge> UniqueEdges(std::span<const Triangle> triangles) {
  std::vector<Edge> edges;
  edges.reserve(triangles.size() * 3);
  for (const Triangle& t : triangles) {
    for (std::size_t e = 0; e < 3; ++e) {
      const std::uint32_t a = t[e], b = t[(e + 1) % 3];
      if (a != b) edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

// Optimal-step ICP of the region in the working frame, one stiffness stage at
// a time. The matrix pattern never changes: full 4x4 blocks on the diagonal
// (data and landmark terms; explicit zeros where a correspondence is
// rejected) plus the diagonal of each edge block (G is diagonal). Only the
// lower triangle is stored (SimplicialLDLT reads the lower part).
class OptimalStepIcp {
 public:
  // Builds the pattern and analyzes it once: every later matrix has it.
  OptimalStepIcp(const IcpRegion& region, const IcpProblem& problem, const ClosestPointQuery& target,
                 const NonrigidIcpParams& params);
  // Stage `stage` of the stiffness schedule; returns its iteration count.
  int RunStage(std::size_t stage, NonrigidIcpResult& result);
  // The fit with its final correspondences; leaves this object spent.
  IcpFit Finish(NonrigidIcpTimings& timings);

 private:
  ClosestPointHit FindTarget(glm::vec3 p, float max_distance) const;
  void FindCorrespondences(NonrigidIcpTimings& timings);
  void SetDataAndLandmarkTerms(double beta);
  void Assemble(double alpha);
  void Factorize(double alpha, NonrigidIcpResult& result);
  double SolveAndDeform(double alpha, NonrigidIcpTimings& timings);

  static constexpr double kRidge = 1e-6;  // keeps parts without any data term solvable

  const IcpRegion& region_;
  const IcpProblem& problem_;
  const ClosestPointQuery& target_;  // target coordinates: queries are mapped in and out of the working frame
  const NonrigidIcpParams& params_;
  std::size_t n_;  // region vertices
  std::vector<Edge> edges_;
  std::vector<double> edge_count_;  // per vertex
  double gamma2_;
  // Per-vertex data and landmark blocks; Assemble adds the stiffness term.
  std::vector<Eigen::Matrix4d> diag_blocks_;
  std::vector<Eigen::Triplet<double>> triplets_;
  Eigen::SparseMatrix<double> matrix_;
  IcpSparseSolver solver_;
  Eigen::MatrixXd x_;  // per-vertex affine transforms (ApplyAffine)
  Eigen::MatrixXd rhs_;
  std::vector<glm::vec3> deformed_, normals_;
  std::vector<ClosestPointHit> hits_;
  std::vector<std::uint8_t> accepted_, weighted_;
  std::vector<double> distances_;
  double cos_limit_;
};

OptimalStepIcp::OptimalStepIcp(const IcpRegion& region, const IcpProblem& problem, const ClosestPointQuery& target,
                               const NonrigidIcpParams& params)
    : region_(region),
      problem_(problem),
      target_(target),
      params_(params),
      n_(region.size()),
      edges_(UniqueEdges(region.triangles)),
      edge_count_(n_, 0.0),
      gamma2_(params.gamma * params.gamma),
      diag_blocks_(n_),
      matrix_(static_cast<Eigen::Index>(4 * n_), static_cast<Eigen::Index>(4 * n_)),
      solver_(params.use_cholmod, n_, edges_),
      x_(Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(4 * n_), 3)),
      rhs_(static_cast<Eigen::Index>(4 * n_), 3),
      deformed_(problem.rest),
      normals_(n_),
      hits_(n_),
      accepted_(n_, 0),
      weighted_(n_, 0),
      cos_limit_(std::cos(params.max_normal_angle_degrees * 3.14159265358979323846 / 180.0)) {
  triplets_.reserve(10 * n_ + 4 * edges_.size());
  for (const auto& [a, b] : edges_) {
    edge_count_[a] += 1.0;
    edge_count_[b] += 1.0;
  }
  for (auto& block : diag_blocks_) block.setIdentity();
  Assemble(1.0);
  solver_.AnalyzePattern(matrix_);
  for (std::size_t i = 0; i < n_; ++i) x_.block<3, 3>(static_cast<Eigen::Index>(4 * i), 0).setIdentity();
}

int OptimalStepIcp::RunStage(std::size_t stage, NonrigidIcpResult& result) {
  const double alpha = params_.stiffness[stage];
  const double beta = params_.landmark_weights.empty()
                          ? 0.0
                          : params_.landmark_weights[std::min(stage, params_.landmark_weights.size() - 1)];
  int iterations = 0;
  for (int iteration = 0; iteration < params_.max_iterations_per_stage; ++iteration) {
    FindCorrespondences(result.timings);
    // The matrix depends only on the stiffness, the landmark weight and
    // which vertices have a data term (not where their correspondences
    // land). The set is fixed at each stage's first iteration, so a stage
    // costs one numeric factorization; later iterations only back-solve.
    // A vertex that loses its correspondence within the stage is pulled
    // to where it is (no force) rather than dropped from the matrix.
    if (iteration == 0) weighted_ = accepted_;
    SetDataAndLandmarkTerms(beta);
    if (iteration == 0) Factorize(alpha, result);
    const double moved = SolveAndDeform(alpha, result.timings);
    ++iterations;
    if (moved / static_cast<double>(n_) < params_.convergence * params_.working_diagonal) break;
  }
  return iterations;
}

IcpFit OptimalStepIcp::Finish(NonrigidIcpTimings& timings) {
  FindCorrespondences(timings);
  return {.transforms = std::move(x_),
          .deformed = std::move(deformed_),
          .hits = std::move(hits_),
          .accepted = std::move(accepted_)};
}

// Nearest target surface point of a working-frame point (working frame in and out).
ClosestPointHit OptimalStepIcp::FindTarget(glm::vec3 p, float max_distance) const {
  const nonrigid_icp_detail::WorkingFrame& frame = problem_.frame;
  ClosestPointHit hit = target_.Find(frame.ToWorld(p), max_distance / frame.to_work_scale);
  if (hit.triangle >= 0) {
    hit.point = frame.ToWork(hit.point);
    hit.distance *= frame.to_work_scale;
  }
  return hit;
}

// Closest points of the deformed region with rejection; fills hits_ and accepted_.
void OptimalStepIcp::FindCorrespondences(NonrigidIcpTimings& timings) {
  const auto t0 = Clock::now();
  ComputeVertexNormals(deformed_, region_.triangles, normals_);
  const auto far_limit = static_cast<float>(params_.max_reject_distance * problem_.target_diagonal_work);
  ParallelFor(n_, 256, [&](std::size_t i) {
    hits_[i] = FindTarget(deformed_[i], far_limit);
    const bool ok = hits_[i].triangle >= 0 && !(params_.reject_boundary && hits_[i].on_boundary) &&
                    glm::dot(normals_[i], hits_[i].normal) >= cos_limit_;
    accepted_[i] = ok ? 1 : 0;
  });
  distances_.clear();
  for (std::size_t i = 0; i < n_; ++i) {
    if (accepted_[i]) distances_.push_back(hits_[i].distance);
  }
  const double median = Percentile(distances_, 0.5);
  const double limit = std::max(params_.distance_median_factor * median,
                                params_.min_reject_distance * problem_.target_diagonal_work);
  for (std::size_t i = 0; i < n_; ++i) {
    if (accepted_[i] && hits_[i].distance > limit) accepted_[i] = 0;
  }
  timings.correspondence_seconds += SecondsSince(t0);
}

// The diagonal blocks and right-hand side of the data term (vertices in
// weighted_) and the landmark term with weight beta.
void OptimalStepIcp::SetDataAndLandmarkTerms(double beta) {
  const std::vector<glm::vec3>& rest = problem_.rest;
  rhs_.setZero();
  for (std::size_t i = 0; i < n_; ++i) {
    const Eigen::Vector4d d(rest[i].x, rest[i].y, rest[i].z, 1.0);
    Eigen::Matrix4d& block = diag_blocks_[i];
    block = kRidge * Eigen::Matrix4d::Identity();
    const auto row = static_cast<Eigen::Index>(4 * i);
    rhs_.block<3, 3>(row, 0) += kRidge * Eigen::Matrix3d::Identity();
    if (weighted_[i]) {
      block += d * d.transpose();
      const glm::vec3 goal = accepted_[i] ? hits_[i].point : deformed_[i];
      const Eigen::RowVector3d u(goal.x, goal.y, goal.z);
      rhs_.block<4, 3>(row, 0) += d * u;
    }
  }
  for (const LocalLandmark& landmark : problem_.landmarks) {
    const glm::vec3 p = rest[landmark.vertex];
    const Eigen::Vector4d d(p.x, p.y, p.z, 1.0);
    const double w = beta * beta * landmark.confidence;
    diag_blocks_[landmark.vertex] += w * d * d.transpose();
    const Eigen::RowVector3d u(landmark.target.x, landmark.target.y, landmark.target.z);
    rhs_.block<4, 3>(static_cast<Eigen::Index>(4 * landmark.vertex), 0) += w * d * u;
  }
}

// Fills matrix_ (pattern fixed) from diag_blocks_ plus the stiffness term for alpha.
void OptimalStepIcp::Assemble(double alpha) {
  triplets_.clear();
  const double a2 = alpha * alpha;
  for (std::size_t i = 0; i < n_; ++i) {
    Eigen::Matrix4d block = diag_blocks_[i];
    for (int k = 0; k < 4; ++k) block(k, k) += a2 * edge_count_[i] * (k == 3 ? gamma2_ : 1.0);
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c <= r; ++c) {
        triplets_.emplace_back(static_cast<Eigen::Index>(4 * i) + r, static_cast<Eigen::Index>(4 * i) + c,
                               block(r, c));
      }
    }
  }
  for (const auto& [a, b] : edges_) {
    for (int k = 0; k < 4; ++k) {
      // Row index larger than column: lower triangle (b > a).
      triplets_.emplace_back(static_cast<Eigen::Index>(4 * b) + k, static_cast<Eigen::Index>(4 * a) + k,
                             -a2 * (k == 3 ? gamma2_ : 1.0));
    }
  }
  matrix_.setFromTriplets(triplets_.begin(), triplets_.end());
}

void OptimalStepIcp::Factorize(double alpha, NonrigidIcpResult& result) {
  Assemble(alpha);
  const auto t0 = Clock::now();
  solver_.Factorize(matrix_);
  ++result.factorizations;
  result.timings.factorize_seconds += SecondsSince(t0);
  if (!solver_.Ok()) {
    throw SolverError("non-rigid ICP: factorization failed at stiffness " + std::to_string(alpha));
  }
}

// One back-solve; moves the region by the new transforms and returns the sum
// of the vertices' displacements.
double OptimalStepIcp::SolveAndDeform(double alpha, NonrigidIcpTimings& timings) {
  const auto t0 = Clock::now();
  Eigen::MatrixXd next = solver_.Solve(rhs_);
  timings.solve_seconds += SecondsSince(t0);
  if (!solver_.Ok() || !next.allFinite()) {
    throw SolverError("non-rigid ICP: the solve failed at stiffness " + std::to_string(alpha));
  }
  x_.swap(next);
  double moved = 0.0;
  for (std::size_t i = 0; i < n_; ++i) {
    const glm::vec3 p = ApplyAffine(x_, i, problem_.rest[i]);
    moved += glm::length(p - deformed_[i]);
    deformed_[i] = p;
  }
  return moved;
}

}  // namespace

NonrigidIcpResult NonrigidIcp(const Mesh& template_mesh, const Mesh& target,
                              const RegistrationLandmarks& landmarks, const NonrigidIcpParams& params) {
  namespace detail = nonrigid_icp_detail;
  const auto start = Clock::now();
  detail::ValidateInputs(template_mesh, target, landmarks, params);
  const IcpRegion region = detail::ExtractRegion(template_mesh, params.region_vertex_count);
  NonrigidIcpResult result;

  const auto rigid_start = Clock::now();
  // One closest-point structure of the target, in its own coordinates, for
  // the rigid step and (queries mapped in and out of the working frame) the
  // non-rigid one: a second copy is slow to build and large on a scan.
  const ClosestPointQuery target_surface(target);
  if (params.rigid_prealign) {
    result.rigid = detail::PreAlign(template_mesh, region, target_surface, landmarks, params.rigid);
  }
  result.timings.rigid_seconds = SecondsSince(rigid_start);

  const auto setup_start = Clock::now();
  const IcpProblem problem =
      detail::BuildProblem(template_mesh, target, region, result.rigid, landmarks, params.working_diagonal);
  result.residual.target_diagonal = problem.target_diagonal;
  OptimalStepIcp icp(region, problem, target_surface, params);
  result.timings.setup_seconds = SecondsSince(setup_start);

  for (std::size_t stage = 0; stage < params.stiffness.size(); ++stage) {
    result.iterations_per_stage.push_back(icp.RunStage(stage, result));
    if (params.progress) params.progress(stage + 1, params.stiffness.size());
  }
  const IcpFit fit = icp.Finish(result.timings);
  detail::WriteRegionFit(region, problem, fit, result);
  detail::CarryInnerVertices(region, problem, fit.transforms, result.positions);
  result.landmark_rms = detail::LandmarkRms(problem, fit.deformed);
  result.timings.total_seconds = SecondsSince(start);
  return result;
}

}  // namespace facerig
