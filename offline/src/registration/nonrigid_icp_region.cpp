// Non-rigid ICP around the solve: input checks, the registered region, rigid
// pre-alignment, the working frame, and mapping the fit back (residuals,
// inner vertices, landmark error).
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <glm/geometric.hpp>

#include "facerig/offline/error.h"
#include "facerig/offline/geometry/stats.h"
#include "registration/nonrigid_icp_impl.h"
#include "geometry/bounding_box.h"

namespace facerig::nonrigid_icp_detail {
namespace {

glm::vec3 BoundsDiagonalVector(std::span<const glm::vec3> points, glm::vec3* lo_out = nullptr) {
  const BoundingBox box = BoxAround(points);
  if (lo_out != nullptr) *lo_out = box.low;
  return box.extent();
}

// RMS distance of the points from their centroid.
double Spread(std::span<const glm::vec3> points) {
  glm::vec3 centre(0.0f);
  for (const glm::vec3& p : points) centre += p / static_cast<float>(points.size());
  double sum = 0.0;
  for (const glm::vec3& p : points) sum += glm::dot(p - centre, p - centre);
  return std::sqrt(sum / static_cast<double>(points.size()));
}

struct LandmarkPairs {
  std::vector<glm::vec3> source;  // template positions
  std::vector<glm::vec3> target;
};

// The similarity comes from the confident landmarks (dlib's jaw points
// follow the silhouette) when at least 6 of them exist, else from all.
LandmarkPairs AlignmentLandmarks(std::span<const glm::vec3> template_positions, const IcpRegion& region,
                                 const RegistrationLandmarks& landmarks) {
  LandmarkPairs pairs;
  for (const float min_confidence : {0.5f, 0.0f}) {
    pairs.source.clear();
    pairs.target.clear();
    for (std::size_t l = 0; l < landmarks.template_vertices.size(); ++l) {
      if (region.local_of[landmarks.template_vertices[l]] == kNotInRegion) continue;
      const float confidence = landmarks.confidence.empty() ? 1.0f : landmarks.confidence[l];
      if (!(confidence > 0.0f) || confidence < min_confidence) continue;
      pairs.source.push_back(template_positions[landmarks.template_vertices[l]]);
      pairs.target.push_back(landmarks.target_points[l]);
    }
    if (pairs.source.size() >= 6) break;
  }
  return pairs;
}

// The target's size from the vertices its triangles use: a stray point far
// away (scans have them) must not loosen the rejection distances or shrink
// the residual percentages.
double SurfaceDiagonal(const Mesh& target) {
  std::vector<std::uint8_t> used(target.vertex_count(), 0);
  for (const Triangle& t : target.triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
  std::vector<glm::vec3> surface_points;
  surface_points.reserve(target.vertex_count());
  for (std::size_t v = 0; v < target.vertex_count(); ++v) {
    if (used[v]) surface_points.push_back(target.positions[v]);
  }
  return glm::length(BoundsDiagonalVector(surface_points));
}

WorkingFrame FrameAround(std::span<const glm::vec3> region_aligned, double working_diagonal) {
  glm::vec3 region_lo;
  const glm::vec3 region_extent = BoundsDiagonalVector(region_aligned, &region_lo);
  const double region_diagonal = glm::length(region_extent);
  if (!(region_diagonal > 0.0)) throw InvalidInputError("non-rigid ICP: the template region is a single point");
  return {.centre = region_lo + 0.5f * region_extent,
          .to_work_scale = static_cast<float>(working_diagonal / region_diagonal)};
}

std::vector<LocalLandmark> RegionLandmarks(const IcpRegion& region, const WorkingFrame& frame,
                                           const RegistrationLandmarks& landmarks) {
  std::vector<LocalLandmark> local_landmarks;
  for (std::size_t l = 0; l < landmarks.template_vertices.size(); ++l) {
    const std::uint32_t local = region.local_of[landmarks.template_vertices[l]];
    const double confidence = landmarks.confidence.empty() ? 1.0 : static_cast<double>(landmarks.confidence[l]);
    if (local == kNotInRegion || !(confidence > 0.0)) continue;
    local_landmarks.push_back({local, frame.ToWork(landmarks.target_points[l]), confidence});
  }
  return local_landmarks;
}

}  // namespace

void ValidateInputs(const Mesh& template_mesh, const Mesh& target, const RegistrationLandmarks& landmarks,
                    const NonrigidIcpParams& params) {
  CheckMesh(template_mesh, "non-rigid ICP template");
  CheckMesh(target, "non-rigid ICP target");
  if (params.stiffness.empty()) throw InvalidInputError("non-rigid ICP: the stiffness schedule is empty");
  const std::size_t landmark_count = landmarks.template_vertices.size();
  if (landmarks.target_points.size() != landmark_count ||
      (!landmarks.confidence.empty() && landmarks.confidence.size() != landmark_count)) {
    throw InvalidInputError("non-rigid ICP: landmark vertices, points and confidences differ in length");
  }
  const std::size_t vertex_count = template_mesh.positions.size();
  for (std::size_t l = 0; l < landmark_count; ++l) {
    if (landmarks.template_vertices[l] >= vertex_count) {
      throw InvalidInputError("non-rigid ICP: landmark " + std::to_string(l) + " uses template vertex " +
                              std::to_string(landmarks.template_vertices[l]) + " of " +
                              std::to_string(vertex_count));
    }
    const glm::vec3 p = landmarks.target_points[l];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw InvalidInputError("non-rigid ICP: landmark " + std::to_string(l) + " is not finite");
    }
  }
}

IcpRegion ExtractRegion(const Mesh& template_mesh, std::uint32_t region_vertex_count) {
  const std::size_t vertex_count = template_mesh.positions.size();
  const std::uint32_t region_limit =
      region_vertex_count == 0
          ? static_cast<std::uint32_t>(vertex_count)
          : std::min<std::uint32_t>(region_vertex_count, static_cast<std::uint32_t>(vertex_count));
  IcpRegion region;
  for (const Triangle& t : template_mesh.triangles) {
    if (t[0] < region_limit && t[1] < region_limit && t[2] < region_limit) region.template_triangles.push_back(t);
  }
  if (region.template_triangles.empty()) {
    throw InvalidInputError("non-rigid ICP: the template region has no triangles");
  }
  region.local_of.assign(vertex_count, kNotInRegion);
  for (const Triangle& t : region.template_triangles) {
    for (std::uint32_t v : t) {
      if (region.local_of[v] == kNotInRegion) {
        region.local_of[v] = static_cast<std::uint32_t>(region.global_of.size());
        region.global_of.push_back(v);
      }
    }
  }
  region.triangles.resize(region.template_triangles.size());
  for (std::size_t t = 0; t < region.triangles.size(); ++t) {
    for (std::size_t k = 0; k < 3; ++k) region.triangles[t][k] = region.local_of[region.template_triangles[t][k]];
  }
  return region;
}

SimilarityTransform PreAlign(const Mesh& template_mesh, const IcpRegion& region, const ClosestPointQuery& target,
                             const RegistrationLandmarks& landmarks, const RigidAlignParams& params) {
  const LandmarkPairs pairs = AlignmentLandmarks(template_mesh.positions, region, landmarks);
  const bool use_landmarks = pairs.source.size() >= 3;
  const RigidAlignResult rigid = RigidAlign(
      Mesh{.positions = template_mesh.positions, .triangles = region.template_triangles}, target,
      use_landmarks ? std::span<const glm::vec3>(pairs.source) : std::span<const glm::vec3>(),
      use_landmarks ? std::span<const glm::vec3>(pairs.target) : std::span<const glm::vec3>(), params, nullptr);
  // Landmarks laid out unlike a face's (a grid on a sheet) can make the
  // best similarity shrink the template to a point.
  if (use_landmarks) {
    const double expected_scale = Spread(pairs.target) / Spread(pairs.source);
    if (!(rigid.transform.scale > 0.01 * expected_scale)) {
      throw InvalidInputError("non-rigid ICP: the landmarks do not match the template's: aligning them shrinks "
                              "the template to a point (scale " + std::to_string(rigid.transform.scale) +
                              ", landmark residual " + std::to_string(rigid.landmark_rms) +
                              "); is the target a face, and are the landmarks right?");
    }
  }
  return rigid.transform;
}

IcpProblem BuildProblem(const Mesh& template_mesh, const Mesh& target, const IcpRegion& region,
                        const SimilarityTransform& rigid, const RegistrationLandmarks& landmarks,
                        double working_diagonal) {
  IcpProblem problem;
  problem.aligned.resize(template_mesh.positions.size());
  for (std::size_t v = 0; v < problem.aligned.size(); ++v) problem.aligned[v] = rigid.Apply(template_mesh.positions[v]);
  std::vector<glm::vec3> region_aligned(region.size());
  for (std::size_t i = 0; i < region.size(); ++i) region_aligned[i] = problem.aligned[region.global_of[i]];
  problem.frame = FrameAround(region_aligned, working_diagonal);
  problem.target_diagonal = SurfaceDiagonal(target);
  problem.target_diagonal_work = problem.target_diagonal * static_cast<double>(problem.frame.to_work_scale);
  problem.rest.resize(region.size());
  for (std::size_t i = 0; i < region.size(); ++i) problem.rest[i] = problem.frame.ToWork(region_aligned[i]);
  problem.landmarks = RegionLandmarks(region, problem.frame, landmarks);
  return problem;
}

void WriteRegionFit(const IcpRegion& region, const IcpProblem& problem, const IcpFit& fit,
                    NonrigidIcpResult& result) {
  const std::size_t vertex_count = region.local_of.size();
  result.positions.assign(vertex_count, glm::vec3(0.0f));
  result.correspondence.assign(vertex_count, SurfaceCorrespondence{});
  std::vector<double> residuals;
  residuals.reserve(region.size());
  for (std::size_t i = 0; i < region.size(); ++i) {
    const std::uint32_t v = region.global_of[i];
    result.positions[v] = problem.frame.ToWorld(fit.deformed[i]);
    if (fit.accepted[i]) {
      result.correspondence[v] = {fit.hits[i].triangle, fit.hits[i].barycentrics};
      residuals.push_back(static_cast<double>(fit.hits[i].distance) / problem.target_diagonal_work * 100.0);
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
}

void CarryInnerVertices(const IcpRegion& region, const IcpProblem& problem, const Eigen::MatrixXd& transforms,
                        std::span<glm::vec3> positions) {
  std::vector<std::uint32_t> inner;
  for (std::uint32_t v = 0; v < region.local_of.size(); ++v) {
    if (region.local_of[v] == kNotInRegion) inner.push_back(v);
  }
  if (inner.empty()) return;
  const ClosestPointQuery rest_surface(
      Mesh{.positions = {problem.rest.begin(), problem.rest.end()}, .triangles = region.triangles});
  for (std::uint32_t v : inner) {
    const glm::vec3 p = problem.frame.ToWork(problem.aligned[v]);
    const ClosestPointHit hit = rest_surface.Find(p);
    const Triangle& t = region.triangles[static_cast<std::size_t>(hit.triangle)];
    glm::vec3 moved(0.0f);
    for (int k = 0; k < 3; ++k) {
      moved += hit.barycentrics[k] * ApplyAffine(transforms, t[static_cast<std::size_t>(k)], p);
    }
    positions[v] = problem.frame.ToWorld(moved);
  }
}

double LandmarkRms(const IcpProblem& problem, std::span<const glm::vec3> deformed) {
  if (problem.landmarks.empty()) return 0.0;
  double sum = 0.0;
  for (const LocalLandmark& landmark : problem.landmarks) {
    const glm::vec3 d = problem.frame.ToWorld(deformed[landmark.vertex]) - problem.frame.ToWorld(landmark.target);
    sum += static_cast<double>(glm::dot(d, d));
  }
  return std::sqrt(sum / static_cast<double>(problem.landmarks.size()));
}

}  // namespace facerig::nonrigid_icp_detail
