// Internal to the deformation transfer files: the per-triangle helpers and
// the precomputed data (DeformationTransferData::Impl) that precompute and solve share.
#pragma once

#include "facerig/offline/geometry/similarity.h"
#include "facerig/offline/transfer/deformation_transfer.h"

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

#include "geometry/bounding_box.h"
#include "openings/contacts.h"
#include "facerig/offline/geometry/stats.h"

namespace facerig {
namespace deformation_transfer_detail {

using Clock = std::chrono::steady_clock;
using Mat32 = Eigen::Matrix<double, 3, 2>;
using Mat23 = Eigen::Matrix<double, 2, 3>;

inline Eigen::Vector3d ToEigen(glm::vec3 p) { return {p.x, p.y, p.z}; }

inline Mat32 Edges(std::span<const glm::vec3> positions, const Triangle& t) {
  const Eigen::Vector3d p0 = ToEigen(positions[t[0]]);
  Mat32 e;
  e.col(0) = ToEigen(positions[t[1]]) - p0;
  e.col(1) = ToEigen(positions[t[2]]) - p0;
  return e;
}

// Local frame [e1 e2 n] of Pawaskar et al.'s eq. 1; with scaled_normal the normal is
// Sumner & Popovic's 4th vertex offset (e1 x e2) / sqrt(|e1 x e2|).
inline Eigen::Matrix3d TriangleFrame(const Mat32& edges, bool scaled_normal) {
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
inline double GramRatio(const Mat32& edges) {
  const Eigen::Matrix2d gram = edges.transpose() * edges;
  const double trace = gram.trace();
  if (!(trace > 0.0)) return 0.0;
  const double det = std::max(0.0, gram.determinant());
  const double disc = std::sqrt(std::max(0.0, 0.25 * trace * trace - det));
  const double largest = 0.5 * trace + disc;
  return (0.5 * trace - disc) / largest;
}

inline void CheckPositions(std::span<const glm::vec3> positions, std::size_t vertex_count,
                    const std::string& mesh) {
  if (positions.size() != vertex_count) {
    throw MeshInputError(mesh, "has " + std::to_string(positions.size()) +
                                       " vertices, expected " + std::to_string(vertex_count));
  }
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const glm::vec3 p = positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw MeshInputError(mesh, "vertex " + std::to_string(v) + " is not finite");
    }
  }
}

inline float BoundingDiagonal(std::span<const glm::vec3> positions) { return BoxAround(positions).diagonal(); }


}  // namespace deformation_transfer_detail
using namespace deformation_transfer_detail;  // NOLINT: internal header of the deformation transfer files

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
  std::optional<ContactFinder> contact_finder;  // with contact_weight > 0 (and still pinning)
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
          TriangleFrame(expression_edges, scaled_normal) * d.source_frame_inverse;
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
      SimilarityTransform transform;  // template rest -> expression (rigid)
      std::vector<std::uint32_t> vertices;
      std::size_t group;  // index of the first fit with the same motion
    };
    std::vector<RigidFit> rigid_fits;
    std::vector<OpeningContact> contacts;
    ContactFinder::Scratch contact_scratch;
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::SparseMatrix<double> system;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  };
  // One expression: returns the residual; scratch.contacts holds the contacts kept.
  double Solve(std::span<const glm::vec3> expression, std::vector<glm::vec3>& out,
               Scratch& scratch) const;
  // The right-hand side rows of the free vertices (free_index >= 0): the
  // accumulated U^T S (3 #V) plus the displacement prior's pull.
  void FillFreeRhs(std::span<const std::int32_t> vertex_free_index, Eigen::Index free_count,
                   const double* accumulated, std::span<const glm::vec3> expression,
                   Eigen::MatrixXd& rhs) const;
  // The free vertices' positions with this expression's still vertices pinned.
  void SolveStillPinned(std::span<const glm::vec3> expression, const double* accumulated,
                        std::vector<glm::vec3>& out, Scratch& scratch) const;
  // Stages of SolveStillPinned, in order.
  // Pins the static anchors and what the expression leaves still; returns the
  // template's largest squared displacement in it.
  float PinStillVertices(std::span<const glm::vec3> expression, Scratch& scratch) const;
  // Pins the gauge of each part with nothing pinned (scratch.floating_components).
  void PinFloatingParts(Scratch& scratch) const;
  // Places the pinned vertices (but the rigid ones, already placed) in out and
  // numbers the others in scratch.free_index; returns their count.
  std::int32_t IndexFreeVertices(std::span<const glm::vec3> expression, std::vector<glm::vec3>& out,
                                 Scratch& scratch) const;
  // scratch.rhs and scratch.triplets: the free rows of full_system, pinned columns
  // moved to the right-hand side, plus the prior.
  void AssembleFreeRows(std::span<const glm::vec3> expression, const double* accumulated,
                        std::int32_t free_count, std::span<const glm::vec3> out, Scratch& scratch) const;
  // Finds the expression's contacts and adds their springs to the free rows.
  void AddContacts(std::span<const glm::vec3> expression, float largest2, std::span<const glm::vec3> out,
                   Scratch& scratch) const;
  // Factorizes the assembled free system and writes the free vertices to out.
  void SolveFreeRows(std::int32_t free_count, std::vector<glm::vec3>& out, Scratch& scratch) const;
  // Pins the unpinned vertices of each part where the template moves them as
  // one rigid body (pinned = kPinnedRigid), placing them rigidly in out.
  void PinRigidMotions(std::span<const glm::vec3> expression, std::vector<glm::vec3>& out,
                       Scratch& scratch) const;
  // Stages of PinRigidMotions: each part's unpinned vertices that the template
  // moves rigidly (scratch.rigid_fits), then each group's placement.
  void FitRigidParts(std::span<const glm::vec3> expression, Scratch& scratch) const;
  void PlaceRigidGroups(std::span<const glm::vec3> expression, std::vector<glm::vec3>& out,
                        Scratch& scratch) const;
  // Translates a part without anchors so that its mean displacement is
  // displacement_scale times the template's.
  void PlaceFloatingPart(std::span<const std::uint32_t> part, std::span<const glm::vec3> expression,
                         std::vector<glm::vec3>& out) const;
  // The weighted root-mean-square gradient residual of a solved expression.
  double Residual(std::span<const glm::vec3> out, const Scratch& scratch) const;
};

}  // namespace facerig
