// What RigidAlign (rigid_align.h) takes and returns, without the algorithm:
// for headers that only pass these on (nonrigid_icp_types.h).
#pragma once

#include <cstddef>

#include "facerig/offline/geometry/similarity.h"

namespace facerig {

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

}  // namespace facerig
