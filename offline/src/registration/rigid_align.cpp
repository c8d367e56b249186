#include "facerig/offline/registration/rigid_align.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <glm/geometric.hpp>

#include "facerig/offline/geometry/closest_point.h"
#include "facerig/offline/error.h"
#include "facerig/offline/geometry/stats.h"
#include "facerig/runtime/rig_builder.h"
#include "geometry/parallel_for.h"

namespace facerig {
namespace {

Eigen::Vector3d ToEigen(glm::vec3 v) { return {v.x, v.y, v.z}; }

bool Finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Eigen::Matrix3d AxisAngle(const Eigen::Vector3d& omega) {
  const double angle = omega.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix();
}

}  // namespace

void CheckMesh(const Mesh& mesh, const char* what) {
  const std::span<const glm::vec3> positions = mesh.positions;
  const std::span<const Triangle> triangles = mesh.triangles;
  if (positions.empty() || triangles.empty()) {
    throw InvalidInputError(std::string(what) + ": the mesh is empty (" + std::to_string(positions.size()) +
                            " vertices, " + std::to_string(triangles.size()) + " triangles)");
  }
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (!Finite(positions[v])) {
      throw InvalidInputError(std::string(what) + ": vertex " + std::to_string(v) +
                              " has a NaN or infinite coordinate");
    }
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (std::uint32_t v : triangles[t]) {
      if (v >= positions.size()) {
        throw InvalidInputError(std::string(what) + ": triangle " + std::to_string(t) + " uses vertex " +
                                std::to_string(v) + " but the mesh has " + std::to_string(positions.size()));
      }
    }
  }
}


RigidAlignResult RigidAlign(const Mesh& source, const Mesh& target_mesh,
                            std::span<const glm::vec3> source_landmarks,
                            std::span<const glm::vec3> target_landmarks, const RigidAlignParams& params,
                            const SimilarityTransform* initial) {
  CheckMesh(target_mesh, "rigid alignment target");
  const ClosestPointQuery target(target_mesh);
  return RigidAlign(source, target, source_landmarks, target_landmarks, params, initial);
}

namespace {

// Vertices used by a triangle with a normal (loose vertices have none),
// thinned to at most max_samples by a stride.
std::vector<std::uint32_t> SampleVertices(std::span<const Triangle> triangles,
                                          std::span<const glm::vec3> normals, std::size_t max_samples) {
  std::vector<std::uint32_t> used;
  std::vector<std::uint8_t> referenced(normals.size(), 0);
  for (const Triangle& t : triangles) {
    for (std::uint32_t v : t) referenced[v] = 1;
  }
  for (std::uint32_t v = 0; v < referenced.size(); ++v) {
    if (referenced[v] && glm::dot(normals[v], normals[v]) > 0.5f) used.push_back(v);
  }
  const std::size_t stride =
      std::max<std::size_t>(1, (used.size() + max_samples - 1) / std::max<std::size_t>(1, max_samples));
  std::vector<std::uint32_t> samples;
  for (std::size_t i = 0; i < used.size(); i += stride) samples.push_back(used[i]);
  if (samples.empty()) throw InvalidInputError("rigid alignment source: no vertex belongs to a triangle");
  return samples;
}

// Centroid and RMS radius of points[index(i)], i < count.
template <typename Index>
std::pair<Eigen::Vector3d, double> Moments(std::span<const glm::vec3> points, Index&& index, std::size_t count) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < count; ++i) mean += ToEigen(points[index(i)]);
  mean /= static_cast<double>(count);
  double variance = 0.0;
  for (std::size_t i = 0; i < count; ++i) variance += (ToEigen(points[index(i)]) - mean).squaredNorm();
  return std::pair{mean, std::sqrt(variance / static_cast<double>(count))};
}

// The ICP's start: from three or more landmarks, else `initial`, else the
// centroids and RMS radii (right scale and position, no rotation).
SimilarityTransform InitialTransform(std::span<const glm::vec3> source_positions,
                                     std::span<const std::uint32_t> samples, const ClosestPointQuery& target,
                                     std::span<const glm::vec3> source_landmarks,
                                     std::span<const glm::vec3> target_landmarks, const RigidAlignParams& params,
                                     const SimilarityTransform* initial) {
  if (source_landmarks.size() >= 3) return Umeyama(source_landmarks, target_landmarks, {}, params.with_scale);
  if (initial != nullptr) return *initial;
  SimilarityTransform transform;
  const auto [source_mean, source_radius] =
      Moments(source_positions, [&](std::size_t i) { return samples[i]; }, samples.size());
  const auto target_points = target.positions();
  const auto [target_mean, target_radius] =
      Moments(target_points, [](std::size_t i) { return i; }, target_points.size());
  transform.scale = params.with_scale && source_radius > 0.0 ? target_radius / source_radius : 1.0;
  transform.translation = target_mean - transform.scale * source_mean;
  return transform;
}

// The transformed samples, their normals, their closest target points and their centre.
struct IcpMatches {
  std::vector<glm::vec3> points, normals;
  std::vector<ClosestPointHit> hits;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
};

void FindMatches(const SimilarityTransform& transform, std::span<const glm::vec3> source_positions,
                 std::span<const glm::vec3> source_normals, std::span<const std::uint32_t> samples,
                 const ClosestPointQuery& target, IcpMatches& matches) {
  ParallelFor(samples.size(), 256, [&](std::size_t i) {
    matches.points[i] = transform.Apply(source_positions[samples[i]]);
    matches.normals[i] = transform.ApplyToDirection(source_normals[samples[i]]);
    matches.hits[i] = target.Find(matches.points[i]);
  });
  matches.centre = Eigen::Vector3d::Zero();
  for (const glm::vec3& point : matches.points) matches.centre += ToEigen(point);
  matches.centre /= static_cast<double>(samples.size());
}

// Matches farther than this are outliers: a multiple of the median distance
// of the compatible ones. Negative when fewer than 6 are compatible.
double OutlierLimit(const IcpMatches& matches, double cos_limit, const RigidAlignParams& params,
                    std::vector<float>& distances) {
  distances.clear();
  for (std::size_t i = 0; i < matches.hits.size(); ++i) {
    const ClosestPointHit& hit = matches.hits[i];
    const bool compatible = glm::dot(matches.normals[i], hit.normal) >= cos_limit;
    if (compatible && !(params.reject_boundary && hit.on_boundary)) distances.push_back(hit.distance);
  }
  if (distances.size() < 6) return -1.0;
  std::nth_element(distances.begin(), distances.begin() + static_cast<std::ptrdiff_t>(distances.size() / 2),
                   distances.end());
  const double median = distances[distances.size() / 2];
  return params.outlier_median_factor * median + 1e-12;
}

// Normal equations of the linearised point-to-plane step about `centre`:
// rotation (3), translation (3), log scale (1).
struct PlaneSystem {
  Eigen::Vector3d centre;
  Eigen::Matrix<double, 7, 7> normal_matrix = Eigen::Matrix<double, 7, 7>::Zero();
  Eigen::Matrix<double, 7, 1> rhs = Eigen::Matrix<double, 7, 1>::Zero();

  void AddRow(const Eigen::Vector3d& p, const Eigen::Vector3d& n, double residual, double w) {
    Eigen::Matrix<double, 7, 1> row;
    const Eigen::Vector3d local = p - centre;
    row.head<3>() = local.cross(n);
    row.segment<3>(3) = n;
    row(6) = n.dot(local);
    normal_matrix.noalias() += w * row * row.transpose();
    rhs.noalias() += w * residual * row;
  }
};

// Adds the inlier matches' rows; returns their count, and their squared distances' sum.
std::size_t AddInlierRows(const IcpMatches& matches, double limit, double cos_limit,
                          const RigidAlignParams& params, PlaneSystem& system, double& squared_sum) {
  std::size_t inliers = 0;
  squared_sum = 0.0;
  for (std::size_t i = 0; i < matches.hits.size(); ++i) {
    const ClosestPointHit& hit = matches.hits[i];
    if (hit.distance > limit || (params.reject_boundary && hit.on_boundary) ||
        glm::dot(matches.normals[i], hit.normal) < cos_limit) {
      continue;
    }
    const Eigen::Vector3d n = ToEigen(hit.normal);
    const Eigen::Vector3d p = ToEigen(matches.points[i]);
    const double residual = n.dot(ToEigen(hit.point) - p);
    system.AddRow(p, n, residual, 1.0);
    squared_sum += static_cast<double>(hit.distance) * hit.distance;
    ++inliers;
  }
  return inliers;
}

void AddLandmarkRows(const SimilarityTransform& transform, std::span<const glm::vec3> source_landmarks,
                     std::span<const glm::vec3> target_landmarks, double w, PlaneSystem& system) {
  for (std::size_t l = 0; l < source_landmarks.size(); ++l) {
    const Eigen::Vector3d p = ToEigen(transform.Apply(source_landmarks[l]));
    const Eigen::Vector3d q = ToEigen(target_landmarks[l]);
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3d n = Eigen::Vector3d::Unit(axis);
      system.AddRow(p, n, q(axis) - p(axis), w);
    }
  }
}

Eigen::Matrix<double, 7, 1> SolveStep(const PlaneSystem& system, int unknowns) {
  Eigen::Matrix<double, 7, 1> delta = Eigen::Matrix<double, 7, 1>::Zero();
  // Tiny Tikhonov term: a flat patch leaves the in-plane motion undetermined.
  const double ridge = 1e-9 * system.normal_matrix.trace();
  const Eigen::MatrixXd a = system.normal_matrix.topLeftCorner(unknowns, unknowns) +
                            ridge * Eigen::MatrixXd::Identity(unknowns, unknowns);
  delta.head(unknowns) = a.ldlt().solve(system.rhs.head(unknowns));
  if (!delta.allFinite()) throw SolverError("rigid alignment: the ICP step is not finite");
  return delta;
}

SimilarityTransform StepTransform(const Eigen::Matrix<double, 7, 1>& delta, const Eigen::Vector3d& centre) {
  SimilarityTransform step;
  step.scale = std::exp(delta(6));
  step.rotation = AxisAngle(delta.head<3>());
  step.translation = centre + delta.segment<3>(3) - step.scale * (step.rotation * centre);
  return step;
}

// The step moved the samples by less than `convergence` of their radius about the centre.
bool StepConverged(const Eigen::Matrix<double, 7, 1>& delta, const IcpMatches& matches, double convergence) {
  double radius = 0.0;
  for (const glm::vec3& p : matches.points) radius = std::max(radius, (ToEigen(p) - matches.centre).norm());
  const double motion = delta.head<3>().norm() * radius + delta.segment<3>(3).norm() +
                        std::abs(delta(6)) * radius;
  return motion < convergence * std::max(radius, 1e-30);
}

double LandmarkRms(const SimilarityTransform& transform, std::span<const glm::vec3> source_landmarks,
                   std::span<const glm::vec3> target_landmarks) {
  double sum = 0.0;
  for (std::size_t l = 0; l < source_landmarks.size(); ++l) {
    sum += static_cast<double>(glm::dot(transform.Apply(source_landmarks[l]) - target_landmarks[l],
                                        transform.Apply(source_landmarks[l]) - target_landmarks[l]));
  }
  return std::sqrt(sum / static_cast<double>(source_landmarks.size()));
}

}  // namespace

RigidAlignResult RigidAlign(const Mesh& source, const ClosestPointQuery& target,
                            std::span<const glm::vec3> source_landmarks,
                            std::span<const glm::vec3> target_landmarks, const RigidAlignParams& params,
                            const SimilarityTransform* initial) {
  const auto start = std::chrono::steady_clock::now();
  CheckMesh(source, "rigid alignment source");
  const std::span<const glm::vec3> source_positions = source.positions;
  const std::span<const Triangle> source_triangles = source.triangles;
  if (source_landmarks.size() != target_landmarks.size()) {
    throw InvalidInputError("rigid alignment: " + std::to_string(source_landmarks.size()) +
                            " source landmarks but " + std::to_string(target_landmarks.size()) +
                            " target landmarks");
  }
  RigidAlignResult result;
  std::vector<glm::vec3> source_normals(source_positions.size());
  ComputeVertexNormals(source_positions, source_triangles, source_normals);
  const std::vector<std::uint32_t> samples = SampleVertices(source_triangles, source_normals, params.max_samples);
  SimilarityTransform transform =
      InitialTransform(source_positions, samples, target, source_landmarks, target_landmarks, params, initial);

  const double cos_limit = std::cos(params.max_normal_angle_degrees * 3.14159265358979323846 / 180.0);
  IcpMatches matches;
  matches.points.resize(samples.size());
  matches.normals.resize(samples.size());
  matches.hits.resize(samples.size());
  std::vector<float> distances;
  const int unknowns = params.with_scale ? 7 : 6;
  for (int iteration = 0; iteration < params.max_iterations; ++iteration) {
    FindMatches(transform, source_positions, source_normals, samples, target, matches);
    const double limit = OutlierLimit(matches, cos_limit, params, distances);
    if (limit < 0.0) break;
    PlaneSystem system;
    system.centre = matches.centre;
    double squared_sum = 0.0;
    const std::size_t inliers = AddInlierRows(matches, limit, cos_limit, params, system, squared_sum);
    if (inliers < 6) break;
    if (iteration == 0) result.rms_initial = std::sqrt(squared_sum / static_cast<double>(inliers));
    result.rms_final = std::sqrt(squared_sum / static_cast<double>(inliers));
    result.inliers = inliers;
    if (!source_landmarks.empty() && params.landmark_weight > 0.0) {
      const double w = params.landmark_weight * static_cast<double>(inliers) /
                       static_cast<double>(source_landmarks.size());
      AddLandmarkRows(transform, source_landmarks, target_landmarks, w, system);
    }
    const Eigen::Matrix<double, 7, 1> delta = SolveStep(system, unknowns);
    transform = StepTransform(delta, matches.centre) * transform;
    result.iterations = iteration + 1;
    if (StepConverged(delta, matches, params.convergence)) break;
  }

  if (!source_landmarks.empty()) result.landmark_rms = LandmarkRms(transform, source_landmarks, target_landmarks);
  result.transform = transform;
  result.seconds = SecondsSince(start);
  return result;
}

}  // namespace facerig
