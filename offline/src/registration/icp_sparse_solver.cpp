#include "registration/icp_sparse_solver.h"

#include <vector>

#include <Eigen/SparseCholesky>
#if defined(FACERIG_HAVE_CHOLMOD)
#include <Eigen/CholmodSupport>
#endif

namespace facerig {

#if defined(FACERIG_HAVE_CHOLMOD)
// CHOLMOD on the matrix permuted by a fill-reducing order computed on the
// vertex graph (nested dissection by METIS, then postordered), each vertex's
// four unknowns kept together: ordering the n-vertex graph is an order of
// magnitude faster than ordering the 4n-unknown one, and the blocks become
// supernode columns.
struct IcpSparseSolver::Cholmod {
  Cholmod(std::size_t vertex_count, std::span<const Edge> vertex_edges);

  Eigen::CholmodSupernodalLLT<Matrix, Eigen::Lower> llt;
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;  // original unknown -> factored row
  Matrix permuted;
  bool ok = true;
};

IcpSparseSolver::Cholmod::Cholmod(std::size_t vertex_count, std::span<const Edge> vertex_edges) {
  const auto n = static_cast<Eigen::Index>(vertex_count);
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(vertex_count + vertex_edges.size());
  for (Eigen::Index v = 0; v < n; ++v) entries.emplace_back(v, v, 1.0);
  for (const auto& [a, b] : vertex_edges) entries.emplace_back(std::max(a, b), std::min(a, b), 1.0);
  Matrix graph(n, n);
  graph.setFromTriplets(entries.begin(), entries.end());
  const Matrix& pattern = graph;
  cholmod_sparse view = Eigen::viewAsCholmod(pattern.selfadjointView<Eigen::Lower>());
  std::vector<int> vertex_order(vertex_count);  // factored position -> vertex
  cholmod_common& common = llt.cholmod();
  ok = vertex_count == 0 || cholmod_metis(&view, nullptr, 0, /*postorder=*/1, vertex_order.data(), &common) != 0;
  order.resize(4 * n);
  for (Eigen::Index p = 0; p < n; ++p) {
    for (int k = 0; k < 4; ++k) order.indices()[4 * vertex_order[p] + k] = static_cast<int>(4 * p + k);
  }
  common.nmethods = 1;
  common.method[0].ordering = CHOLMOD_NATURAL;
  common.postorder = 0;
  // Larger relaxed supernodes than CHOLMOD's defaults (4/16/48 columns): a
  // few more explicit zeros, but longer dense BLAS-3 runs on this pattern.
  common.nrelax[0] = 16;
  common.nrelax[1] = 64;
  common.nrelax[2] = 128;
  common.zrelax[0] = 0.9;
  common.zrelax[1] = 0.3;
  common.zrelax[2] = 0.1;
}
#else
struct IcpSparseSolver::Cholmod {};
#endif

struct IcpSparseSolver::Simplicial {
  Eigen::SimplicialLDLT<Matrix, Eigen::Lower> ldlt;
};

IcpSparseSolver::IcpSparseSolver(bool prefer_cholmod, std::size_t vertex_count,
                                 std::span<const Edge> vertex_edges) {
#if defined(FACERIG_HAVE_CHOLMOD)
  if (prefer_cholmod) {
    cholmod_ = std::make_unique<Cholmod>(vertex_count, vertex_edges);
    return;
  }
#else
  (void)prefer_cholmod, (void)vertex_count, (void)vertex_edges;
#endif
  simplicial_ = std::make_unique<Simplicial>();
}

IcpSparseSolver::~IcpSparseSolver() = default;

void IcpSparseSolver::AnalyzePattern(const Matrix& matrix) {
#if defined(FACERIG_HAVE_CHOLMOD)
  if (cholmod_) {
    cholmod_->permuted.resize(matrix.rows(), matrix.cols());
    cholmod_->permuted.selfadjointView<Eigen::Lower>() =
        matrix.selfadjointView<Eigen::Lower>().twistedBy(cholmod_->order);
    if (cholmod_->ok) cholmod_->llt.analyzePattern(cholmod_->permuted);
    return;
  }
#endif
  simplicial_->ldlt.analyzePattern(matrix);
}

void IcpSparseSolver::Factorize(const Matrix& matrix) {
#if defined(FACERIG_HAVE_CHOLMOD)
  if (cholmod_) {
    cholmod_->permuted.selfadjointView<Eigen::Lower>() =
        matrix.selfadjointView<Eigen::Lower>().twistedBy(cholmod_->order);
    if (cholmod_->ok) cholmod_->llt.factorize(cholmod_->permuted);
    return;
  }
#endif
  simplicial_->ldlt.factorize(matrix);
}

Eigen::MatrixXd IcpSparseSolver::Solve(const Eigen::MatrixXd& rhs) const {
#if defined(FACERIG_HAVE_CHOLMOD)
  if (cholmod_) return cholmod_->order.inverse() * cholmod_->llt.solve(cholmod_->order * rhs).eval();
#endif
  return simplicial_->ldlt.solve(rhs);
}

bool IcpSparseSolver::Ok() const {
#if defined(FACERIG_HAVE_CHOLMOD)
  if (cholmod_) return cholmod_->ok && cholmod_->llt.info() == Eigen::Success;
#endif
  return simplicial_->ldlt.info() == Eigen::Success;
}

}  // namespace facerig
