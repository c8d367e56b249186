// Deformation transfer (Sumner & Popovic 2004, as in Pawaskar et al.'s Algorithm 1):
// a template's expressions S_1..S_k, given as whole meshes in per-vertex
// correspondence with its neutral S_0, are transferred onto a target neutral
// T_0 of the same topology (or a template fitted to the target).
//
// libigl-style pair: PrecomputeDeformationTransfer assembles the sparse normal
// equations U^T U once per target; SolveDeformationTransfer solves one
// expression. By default (still pinning, DeformationTransferParams::
// still_fraction > 0) each expression pins what it leaves still and factorizes
// the system of the vertices it moves: one small factorization per expression.
// With still_fraction = 0 the precomputation factorizes one system shared by
// every expression, and each solve is a back-substitution. DeformationTransfer
// does both for a whole set of expressions on several threads (results do not
// depend on the thread count).
//
// Positions are in the meshes' own units; both meshes are expected in the
// same frame and at a similar scale (rigidly aligned).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "facerig/offline/error.h"
#include "facerig/offline/geometry/stats.h"
#include "facerig/offline/openings/openings.h"
#include "facerig/offline/transfer/deformation_transfer_types.h"
#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {

// The sparse factorization failed (a part of the mesh without an anchor that
// the automatic anchoring could not fix, or non-finite geometry).
class TransferSolverError : public SolverError {
 public:
  using SolverError::SolverError;
};

// The assembled (and, without still pinning, factorized) system for one
// target (one source neutral / target neutral pair and one anchor set). Movable; used read-only by the solves, so one
// instance serves several threads.
struct DeformationTransferData {
  DeformationTransferData();
  ~DeformationTransferData();
  DeformationTransferData(DeformationTransferData&&) noexcept;
  DeformationTransferData& operator=(DeformationTransferData&&) noexcept;

  std::size_t vertex_count = 0;
  std::size_t triangle_count = 0;
  std::size_t anchor_count = 0;
  std::size_t free_count = 0;          // unknowns of the sparse system
  std::size_t component_count = 0;     // connected parts of the mesh
  std::size_t floating_components = 0;  // parts anchored by their mean displacement
  std::size_t regularized_triangles = 0;  // needle / degenerate triangles clamped
  // Contacts are kept: contact_weight > 0 and still pinning on (still_fraction > 0).
  bool contacts_active = false;
  double factorize_seconds = 0.0;
  double precompute_seconds = 0.0;  // total, including the factorization

  struct Impl;
  std::unique_ptr<Impl> impl;
};

// Builds the system for a target (and factorizes it when still_fraction is 0).
// source: the template's neutral mesh; target_neutral: #V positions on its topology.
// source_expressions: the template's expressions (each #V), used only to find
// the static anchor set when params.anchor_vertices is empty (may then not be empty).
// \throw MeshInputError on mismatched sizes or bad indices (naming the mesh);
// \throw TransferSolverError when the factorization fails.
void PrecomputeDeformationTransfer(const Mesh& source, std::span<const glm::vec3> target_neutral,
                                   std::span<const std::vector<glm::vec3>> source_expressions,
                                   const DeformationTransferParams& params,
                                   DeformationTransferData& data);

// One expression: source_expression (#V) -> target_expression (#V, resized).
// Returns the root-mean-square gradient residual (weighted, dimensionless).
// \throw MeshInputError when source_expression has the wrong size.
double SolveDeformationTransfer(const DeformationTransferData& data,
                                std::span<const glm::vec3> source_expression,
                                std::vector<glm::vec3>& target_expression);

// Precompute + one solve per expression, expressions spread over params.threads.
DeformationTransferResult DeformationTransfer(const Mesh& source, std::span<const glm::vec3> target_neutral,
                                              std::span<const std::vector<glm::vec3>> source_expressions,
                                              const DeformationTransferParams& params = {});

// The rig's neutral and every shape applied at weight 1 (dense, #V each).
std::vector<std::vector<glm::vec3>> RigExpressionMeshes(const Rig& rig);

// Sparse blend shapes (expression - neutral), keeping deltas longer than
// relative_drop_threshold times the neutral's bounding-box diagonal.
// \pre names.size() == expressions.size(); each expression has #V positions.
std::vector<RawBlendShape> MakeBlendShapes(std::span<const std::string> names,
                                           std::span<const glm::vec3> neutral,
                                           std::span<const std::vector<glm::vec3>> expressions,
                                           float relative_drop_threshold = 1e-6f);

// A copy of the template rig (topology, UVs, parts, units, shape names) with
// target_neutral as its neutral and the template's shapes transferred onto it
// by deformation transfer. \pre target_neutral.size() == rig.vertex_count().
// \throw MeshInputError, TransferSolverError.
RawRig TransferRig(const Rig& template_rig, std::span<const glm::vec3> target_neutral,
                   const DeformationTransferParams& params = {},
                   DeformationTransferResult* result = nullptr);

// How closed an opening is (eyelid and lip margins, their gap): openings.h.

}  // namespace facerig
