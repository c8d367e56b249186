// The stages of NonrigidIcp (facerig/offline/nonrigid_icp.h) and the state
// they hand on. nonrigid_icp.cpp holds the entry point and the stiffness
// schedule (its sparse solve is the one source built with CHOLMOD);
// nonrigid_icp_region.cpp prepares the problem (input checks, the registered
// region, rigid pre-alignment, the working frame) and maps the fit back.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <glm/vec3.hpp>

#include "facerig/offline/geometry/closest_point.h"
#include "facerig/offline/registration/nonrigid_icp.h"
#include "facerig/offline/registration/rigid_align.h"
#include "facerig/runtime/mesh.h"

namespace facerig::nonrigid_icp_detail {

inline constexpr std::uint32_t kNotInRegion = 0xffffffffu;

// The registered region: the template triangles whose three vertices are all
// below the region limit, and the vertices they use, re-indexed 0..size()-1.
struct IcpRegion {
  std::vector<Triangle> template_triangles;  // template vertex indices
  std::vector<Triangle> triangles;  // the same triangles, local indices
  std::vector<std::uint32_t> local_of;  // #template vertices: local index or kNotInRegion
  std::vector<std::uint32_t> global_of;  // local index -> template vertex
  std::size_t size() const { return global_of.size(); }
};

// The frame the problem is solved in: the rigidly aligned template region
// centred, its bounding-box diagonal NonrigidIcpParams::working_diagonal, so
// that stiffness and landmark weights do not depend on the meshes' units.
struct WorkingFrame {
  glm::vec3 centre{0.0f};
  float to_work_scale = 1.0f;
  glm::vec3 ToWork(glm::vec3 p) const { return (p - centre) * to_work_scale; }
  glm::vec3 ToWorld(glm::vec3 p) const { return p / to_work_scale + centre; }
};

// A landmark on the region: local vertex, working-frame target, weight factor.
struct LocalLandmark {
  std::uint32_t vertex;
  glm::vec3 target;
  double confidence;
};

// What the stiffness schedule reads.
struct IcpProblem {
  WorkingFrame frame;
  std::vector<glm::vec3> aligned;  // #template vertices after the rigid pre-alignment, target coordinates
  std::vector<glm::vec3> rest;  // undeformed region, working frame
  std::vector<LocalLandmark> landmarks;  // confident landmarks on the region
  double target_diagonal = 0.0;  // target units, from the vertices its triangles use
  double target_diagonal_work = 0.0;  // the same in the working frame
};

// The fit: per-vertex affine transforms, the deformed region and its final
// correspondences (all working frame).
struct IcpFit {
  Eigen::MatrixXd transforms;  // 4 #region x 3, see ApplyAffine
  std::vector<glm::vec3> deformed;  // #region
  std::vector<ClosestPointHit> hits;  // #region
  std::vector<std::uint8_t> accepted;  // #region: 1 where the hit passed the rejection tests
};

// Per-vertex affine transform X_i (4 x 3, rows: linear part, then translation)
// applied to a point: X_i^T [p; 1].
inline glm::vec3 ApplyAffine(const Eigen::MatrixXd& x, std::size_t vertex, glm::vec3 p) {
  const auto row = static_cast<Eigen::Index>(4 * vertex);
  glm::vec3 out;
  for (int c = 0; c < 3; ++c) {
    out[c] = static_cast<float>(x(row, c) * p.x + x(row + 1, c) * p.y + x(row + 2, c) * p.z + x(row + 3, c));
  }
  return out;
}

// \throw InvalidInputError as NonrigidIcp documents.
void ValidateInputs(const Mesh& template_mesh, const Mesh& target, const RegistrationLandmarks& landmarks,
                    const NonrigidIcpParams& params);

// \throw InvalidInputError when the region has no triangles.
IcpRegion ExtractRegion(const Mesh& template_mesh, std::uint32_t region_vertex_count);

// Similarity template -> target from the region's landmarks (or from the
// surfaces alone when fewer than 3 are usable).
// \throw InvalidInputError when the landmarks shrink the template to a point.
SimilarityTransform PreAlign(const Mesh& template_mesh, const IcpRegion& region, const ClosestPointQuery& target,
                             const RegistrationLandmarks& landmarks, const RigidAlignParams& params);

// \throw InvalidInputError when the aligned region is a single point.
IcpProblem BuildProblem(const Mesh& template_mesh, const Mesh& target, const IcpRegion& region,
                        const SimilarityTransform& rigid, const RegistrationLandmarks& landmarks,
                        double working_diagonal);

// Region vertices' positions and correspondences in `result` (sized to the
// template, inner vertices at the origin) and the residual statistics.
void WriteRegionFit(const IcpRegion& region, const IcpProblem& problem, const IcpFit& fit,
                    NonrigidIcpResult& result);

// Inner (non-region) vertices: each takes the affine transforms of its nearest
// point on the undeformed region surface (barycentric blend), so eyeballs,
// teeth and the mouth socket move with the skin around them.
void CarryInnerVertices(const IcpRegion& region, const IcpProblem& problem, const Eigen::MatrixXd& transforms,
                        std::span<glm::vec3> positions);

// RMS distance of the fitted landmark vertices to their targets, target units; 0 without landmarks.
double LandmarkRms(const IcpProblem& problem, std::span<const glm::vec3> deformed);

}  // namespace facerig::nonrigid_icp_detail
