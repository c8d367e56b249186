// The sparse Cholesky solver of non-rigid ICP's 4n x 4n normal equations.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <utility>

#include <Eigen/Core>
#include <Eigen/Sparse>

namespace facerig {

// Supernodal CHOLMOD when the build has it and the caller wants it (much
// faster), else Eigen's simplicial LDL^T; the choice is at run time so a
// benchmark can run both. The symbolic analysis is done once: every later
// matrix must have the analyzed pattern (lower triangle stored).
class IcpSparseSolver {
 public:
  using Matrix = Eigen::SparseMatrix<double>;
  using Edge = std::pair<std::uint32_t, std::uint32_t>;

  // `vertex_edges` are the edges of the n-vertex graph whose 4 x 4 blocks
  // make the matrix's pattern (unknowns 4v..4v+3 belong to vertex v).
  IcpSparseSolver(bool prefer_cholmod, std::size_t vertex_count, std::span<const Edge> vertex_edges);
  ~IcpSparseSolver();
  IcpSparseSolver(const IcpSparseSolver&) = delete;
  IcpSparseSolver& operator=(const IcpSparseSolver&) = delete;

  void AnalyzePattern(const Matrix& matrix);
  void Factorize(const Matrix& matrix);
  Eigen::MatrixXd Solve(const Eigen::MatrixXd& rhs) const;
  bool Ok() const;

 private:
  struct Cholmod;
  struct Simplicial;
  std::unique_ptr<Cholmod> cholmod_;
  std::unique_ptr<Simplicial> simplicial_;
};

}  // namespace facerig
