// Rigid (similarity) alignment of a source mesh onto a target mesh: Umeyama's
// closed form from landmark pairs, refined by point-to-plane ICP with outlier
// rejection. Scale is estimated, so metres vs centimetres (ratio 100) works.
//
// Positions in each mesh's own units; the transform maps source coordinates
// to target coordinates: x_target = scale * rotation * x_source + translation.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <glm/vec3.hpp>

#include "facerig/offline/geometry/similarity.h"
#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"

namespace facerig {

class ClosestPointQuery;

struct RigidAlignParams {
  int max_iterations = 40;
  bool with_scale = true;
  // Stop when the update moves the source by less than this fraction of its
  // bounding-box diagonal.
  double convergence = 1e-5;
  // Reject pairs farther than this multiple of the median pair distance...
  double outlier_median_factor = 2.5;
  // ...and pairs whose normals differ by more than this (degrees).
  double max_normal_angle_degrees = 60.0;
  // Reject pairs that land on the target's boundary (edges of a partial scan).
  bool reject_boundary = true;
  // At most this many source vertices are used per iteration (evenly strided).
  std::size_t max_samples = 6000;
  // Weight of the landmark pairs relative to all surface pairs together
  // (0: landmarks only seed the initial transform).
  double landmark_weight = 0.1;
};

struct RigidAlignResult {
  SimilarityTransform transform;  // source -> target
  int iterations = 0;
  // RMS point-to-surface distance of the inlier pairs, in target units.
  double rms_initial = 0.0;
  double rms_final = 0.0;
  std::size_t inliers = 0;  // pairs kept in the last iteration
  double landmark_rms = 0.0;  // after alignment, target units (0 without landmarks)
  double seconds = 0.0;
};

// Aligns the source mesh onto the target. With >= 3 landmark pairs
// (source_landmarks[i] on the source <-> target_landmarks[i] on the target)
// the start is their Umeyama transform, else `initial` when given, else the
// centroids and RMS radii of the vertex sets (no rotation).
// \throw InvalidInputError on empty meshes, NaN coordinates, mismatched
//        landmark counts.
RigidAlignResult RigidAlign(const Mesh& source, const Mesh& target,
                            std::span<const glm::vec3> source_landmarks = {},
                            std::span<const glm::vec3> target_landmarks = {},
                            const RigidAlignParams& params = {},
                            const SimilarityTransform* initial = nullptr);

// The same with a prebuilt closest-point structure of the target.
RigidAlignResult RigidAlign(const Mesh& source, const ClosestPointQuery& target,
                            std::span<const glm::vec3> source_landmarks,
                            std::span<const glm::vec3> target_landmarks, const RigidAlignParams& params,
                            const SimilarityTransform* initial);

// Checks positions for non-finite values and triangles for indices out of
// range. \throw InvalidInputError naming `what` and the vertex/triangle.
void CheckMesh(const Mesh& mesh, const char* what);

}  // namespace facerig
