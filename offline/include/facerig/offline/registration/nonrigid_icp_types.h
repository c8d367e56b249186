// What NonrigidIcp (nonrigid_icp.h) takes and returns, without the
// algorithm: for headers that only pass these on (rig_build.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

#include "facerig/offline/geometry/similarity.h"
#include "facerig/offline/registration/rigid_align_types.h"

namespace facerig {

struct NonrigidIcpParams {
  // Template vertices [0, region_vertex_count) are registered (their
  // triangles define the template surface); the rest (inner parts: eyeballs,
  // teeth, mouth socket, lashes) follow the fitted surface. 0: all vertices.
  // A template's descriptor gives it (FaceTemplateInfo::region).
  std::uint32_t region_vertex_count = 0;
  // Stiffness per stage (stiff to soft) and the landmark weight per stage
  // (same length; a shorter landmark list repeats its last value).
  std::vector<double> stiffness{50.0, 20.0, 5.0, 2.0, 0.8, 0.5};
  std::vector<double> landmark_weights{10.0, 5.0, 3.0, 2.0, 1.0, 0.5};
  // Optimal-step iterations per stage: stop when the mean vertex update is
  // below `convergence` (fraction of the working diagonal) or after this many.
  int max_iterations_per_stage = 4;
  double convergence = 2e-4;
  // Weight of the translation column against the linear part in the stiffness term.
  double gamma = 1.0;
  double working_diagonal = 100.0;
  // Correspondence rejection: normal angle (degrees), target boundary,
  // distance beyond max(distance_median_factor * median, min_reject_distance)
  // (the latter a fraction of the target diagonal).
  double max_normal_angle_degrees = 60.0;
  bool reject_boundary = true;
  double distance_median_factor = 4.0;
  double min_reject_distance = 0.01;
  double max_reject_distance = 0.1;
  // Rigid pre-alignment (needs >= 3 landmarks; otherwise the template is
  // assumed to be roughly aligned with the target already and only ICP runs).
  bool rigid_prealign = true;
  // Sparse Cholesky: supernodal CHOLMOD when the build links it (FACERIG_WITH_CHOLMOD),
  // else, or when false, Eigen's simplicial LDL^T (same result, slower).
  bool use_cholmod = true;
  RigidAlignParams rigid;
  // Called after each stage with (stages done, stage count); may be empty.
  std::function<void(std::size_t, std::size_t)> progress;
};

// Landmark pairs: template vertex <-> target point, with a confidence in [0, 1]
// (e.g. low for dlib's jaw points, which follow the silhouette).
struct RegistrationLandmarks {
  std::vector<std::uint32_t> template_vertices;
  std::vector<glm::vec3> target_points;
  std::vector<float> confidence;  // empty: all 1
};

struct SurfaceCorrespondence {
  std::int32_t triangle = -1;  // target triangle, -1: none (inner vertex or rejected)
  glm::vec3 barycentrics{0.0f};
};

// Distances from the fitted region vertices to the target surface, as a
// percentage of the target's bounding-box diagonal.
struct ResidualStats {
  double mean_percent = 0.0;
  double p95_percent = 0.0;
  double max_percent = 0.0;
  double target_diagonal = 0.0;  // target units
  std::size_t vertex_count = 0;  // vertices measured (accepted correspondences)
  std::size_t rejected_count = 0;  // region vertices whose correspondence was rejected
};

struct NonrigidIcpTimings {
  double rigid_seconds = 0.0;
  double setup_seconds = 0.0;  // closest-point structure, pattern, symbolic analysis
  double correspondence_seconds = 0.0;
  double factorize_seconds = 0.0;
  double solve_seconds = 0.0;
  double total_seconds = 0.0;
};

struct NonrigidIcpResult {
  std::vector<glm::vec3> positions;  // #template vertices, target coordinates
  std::vector<SurfaceCorrespondence> correspondence;  // #template vertices
  SimilarityTransform rigid;  // template -> target, before the non-rigid fit
  ResidualStats residual;
  NonrigidIcpTimings timings;
  std::vector<int> iterations_per_stage;
  int factorizations = 0;  // numeric factorizations: one per stage (one symbolic analysis)
  double landmark_rms = 0.0;  // fitted landmark vertices vs target points, target units
};

}  // namespace facerig
