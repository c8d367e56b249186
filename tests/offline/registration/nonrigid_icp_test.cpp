#include "facerig/offline/registration/nonrigid_icp.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/error.h"
#include "support/ict_faces.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

// An n x n grid over [-1, 1]^2 bent by `bend` (a smooth height field).
void MakeSheet(int n, float bend, std::vector<glm::vec3>& positions, std::vector<Triangle>& triangles) {
  positions.clear();
  triangles.clear();
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const float u = -1.0f + 2.0f * static_cast<float>(x) / static_cast<float>(n - 1);
      const float v = -1.0f + 2.0f * static_cast<float>(y) / static_cast<float>(n - 1);
      positions.push_back({u, v, bend * (0.5f * u * u - 0.3f * v * v + 0.2f * u * v)});
    }
  }
  for (int y = 0; y + 1 < n; ++y) {
    for (int x = 0; x + 1 < n; ++x) {
      const auto a = static_cast<std::uint32_t>(y * n + x);
      const auto b = a + 1, c = a + static_cast<std::uint32_t>(n), d = c + 1;
      triangles.push_back({a, b, d});
      triangles.push_back({a, d, c});
    }
  }
}

// Landmarks at `vertices` of a MakeSheet source, each placed on the target
// sheet's bend (`target_bend`) above the same (x, y).
RegistrationLandmarks SheetLandmarks(const std::vector<glm::vec3>& source,
                                     std::initializer_list<std::uint32_t> vertices, float target_bend) {
  RegistrationLandmarks landmarks;
  for (std::uint32_t v : vertices) {
    landmarks.template_vertices.push_back(v);
    glm::vec3 p = source[v];
    p.z = target_bend * (0.5f * p.x * p.x - 0.3f * p.y * p.y + 0.2f * p.x * p.y);
    landmarks.target_points.push_back(p);
  }
  return landmarks;
}

// The largest height difference between `positions` and the sheet bent by
// `bend`, away from the sheet's border (|x|, |y| < 0.9).
double WorstHeightError(const std::vector<glm::vec3>& positions, double bend) {
  double worst = 0.0;
  for (const glm::vec3& p : positions) {
    const double z = bend * (0.5 * p.x * p.x - 0.3 * p.y * p.y + 0.2 * p.x * p.y);
    if (std::abs(p.x) < 0.9f && std::abs(p.y) < 0.9f) worst = std::max(worst, std::abs(z - p.z));
  }
  return worst;
}

struct FitReport {
  double correspondence_mean_cm = 0.0;
  double correspondence_p95_cm = 0.0;
};

FitReport Measure(const NonrigidIcpResult& fit, const test::RegistrationTarget& target) {
  std::vector<double> errors;
  for (std::uint32_t v = 0; v < test::IctFaces().face_vertex_count(); ++v) {
    errors.push_back(static_cast<double>(glm::length(fit.positions[v] - target.true_ict_positions[v])) /
                     target.units_per_cm);
  }
  FitReport report;
  for (double e : errors) report.correspondence_mean_cm += e;
  report.correspondence_mean_cm /= static_cast<double>(errors.size());
  std::sort(errors.begin(), errors.end());
  report.correspondence_p95_cm = errors[errors.size() * 95 / 100];
  return report;
}

RegistrationLandmarks IctLandmarks(const test::RegistrationTarget& target) {
  RegistrationLandmarks landmarks;
  landmarks.template_vertices = test::IctFaces().info.landmark_vertices;
  landmarks.target_points = target.true_landmarks;
  landmarks.confidence.assign(68, 1.0f);
  for (int i = 0; i < 17; ++i) landmarks.confidence[static_cast<std::size_t>(i)] = 0.2f;  // jaw
  return landmarks;
}

TEST_CASE("Non-rigid ICP fits a bent sheet onto another bend", "[nonrigid_icp]") {
  std::vector<glm::vec3> source, target;
  std::vector<Triangle> source_triangles, target_triangles;
  MakeSheet(30, 0.2f, source, source_triangles);
  MakeSheet(41, 0.6f, target, target_triangles);  // a different vertex set
  // Scan-like defects: degenerate triangles and a loose vertex.
  target_triangles.push_back({5, 5, 6});
  target_triangles.push_back({7, 8, 7});
  target.push_back({0.0f, 0.0f, 0.0f});
  const RegistrationLandmarks landmarks = SheetLandmarks(source, {0u, 29u, 870u, 899u, 435u}, 0.6f);
  const NonrigidIcpResult fit = NonrigidIcp(facerig::test::MeshOf(source, source_triangles), facerig::test::MeshOf(target, target_triangles), landmarks);
  REQUIRE(fit.positions.size() == source.size());
  CHECK(fit.residual.mean_percent < 0.1);
  CHECK(fit.residual.p95_percent < 0.3);
  // Heights follow the target's bend.
  CHECK(WorstHeightError(fit.positions, 0.6) < 0.01);
  CHECK(fit.iterations_per_stage.size() == 6);
  int correspondences = 0;
  for (const SurfaceCorrespondence& c : fit.correspondence) correspondences += c.triangle >= 0 ? 1 : 0;
  CHECK(correspondences > 800);
}

TEST_CASE("Non-rigid ICP: CHOLMOD and Eigen's simplicial solver give the same fit", "[nonrigid_icp]") {
  std::vector<glm::vec3> source, target;
  std::vector<Triangle> source_triangles, target_triangles;
  MakeSheet(20, 0.2f, source, source_triangles);
  MakeSheet(27, 0.6f, target, target_triangles);
  const RegistrationLandmarks landmarks = SheetLandmarks(source, {0u, 19u, 380u, 399u, 210u}, 0.6f);
  NonrigidIcpParams params;
  params.use_cholmod = true;
  const NonrigidIcpResult preferred =
      NonrigidIcp(facerig::test::MeshOf(source, source_triangles), facerig::test::MeshOf(target, target_triangles), landmarks, params);
  params.use_cholmod = false;
  const NonrigidIcpResult simplicial =
      NonrigidIcp(facerig::test::MeshOf(source, source_triangles), facerig::test::MeshOf(target, target_triangles), landmarks, params);
  REQUIRE(preferred.positions.size() == simplicial.positions.size());
  float worst = 0.0f;
  for (std::size_t v = 0; v < source.size(); ++v) {
    worst = std::max(worst, glm::length(preferred.positions[v] - simplicial.positions[v]));
  }
  CHECK(worst < 1e-4f);  // the sheet is 2 units wide: both solve the same system
  CHECK(preferred.factorizations == simplicial.factorizations);
}

// Scan defects of issue 5 on a target: fins (edges with three or four
// triangles), a duplicated triangle, degenerate triangles (repeated index,
// collinear) and isolated vertices, one of them far away. Returns how many
// triangles were added.
std::size_t AddNonManifoldDefects(std::vector<glm::vec3>& positions, std::vector<Triangle>& triangles,
                                  std::size_t fins, float fin_depth) {
  const std::size_t original = triangles.size();
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const glm::vec3& p : positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const float diagonal = glm::length(hi - lo);
  const std::size_t stride = std::max<std::size_t>(1, original / (fins + 1));
  for (std::size_t k = 1; k <= fins; ++k) {
    const Triangle t = triangles[(k * stride) % original];
    const glm::vec3 a = positions[t[0]], b = positions[t[1]], c = positions[t[2]];
    const glm::vec3 normal = glm::normalize(glm::cross(b - a, c - a));
    // A small fin hanging behind the surface from edge (a, b): that edge now
    // has three triangles; the second fin on it makes four.
    const auto tip = static_cast<std::uint32_t>(positions.size());
    positions.push_back((a + b + c) / 3.0f - fin_depth * diagonal * normal);
    triangles.push_back({t[0], t[1], tip});
    if (k % 4 == 0) triangles.push_back({t[1], t[0], tip});
    if (k % 5 == 0) triangles.push_back(t);  // duplicate
    if (k % 3 == 0) triangles.push_back({t[0], t[0], t[1]});  // repeated index
    if (k % 3 == 1) {  // collinear: zero area, three distinct vertices
      const auto mid = static_cast<std::uint32_t>(positions.size());
      positions.push_back(0.5f * (a + b));
      triangles.push_back({t[0], mid, t[1]});
    }
  }
  for (int k = 0; k < 20; ++k) {  // isolated vertices inside the bounds
    const float f = static_cast<float>(k) / 20.0f;
    positions.push_back(lo + f * (hi - lo));
  }
  positions.push_back(hi + 100.0f * (hi - lo));  // a stray point far away
  return triangles.size() - original;
}

TEST_CASE("Non-rigid ICP on a non-manifold target with stray points", "[nonrigid_icp]") {
  std::vector<glm::vec3> source, target;
  std::vector<Triangle> source_triangles, target_triangles;
  MakeSheet(30, 0.2f, source, source_triangles);
  MakeSheet(41, 0.6f, target, target_triangles);
  const std::size_t clean_vertices = target.size();
  CHECK(AddNonManifoldDefects(target, target_triangles, 40, 0.002f) > 40);
  const RegistrationLandmarks landmarks = SheetLandmarks(source, {0u, 29u, 870u, 899u, 435u}, 0.6f);
  const NonrigidIcpResult fit = NonrigidIcp(facerig::test::MeshOf(source, source_triangles), facerig::test::MeshOf(target, target_triangles), landmarks);
  REQUIRE(fit.positions.size() == source.size());
  // The far stray point does not count in the target's size...
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (std::size_t v = 0; v < clean_vertices; ++v) {
    lo = glm::min(lo, target[v]);
    hi = glm::max(hi, target[v]);
  }
  CHECK(fit.residual.target_diagonal == Approx(glm::length(hi - lo)).epsilon(1e-3));
  // ...and the fit is as good as on the clean sheet.
  CHECK(fit.residual.mean_percent < 0.1);
  CHECK(WorstHeightError(fit.positions, 0.6) < 0.01);
}

TEST_CASE("Non-rigid ICP rejects invalid input", "[nonrigid_icp]") {
  std::vector<glm::vec3> sheet;
  std::vector<Triangle> triangles;
  MakeSheet(5, 0.1f, sheet, triangles);
  CHECK_THROWS_AS(NonrigidIcp(facerig::test::MeshOf({}, {}), facerig::test::MeshOf(sheet, triangles), {}), InvalidInputError);
  CHECK_THROWS_AS(NonrigidIcp(facerig::test::MeshOf(sheet, triangles), facerig::test::MeshOf({}, {}), {}), InvalidInputError);
  std::vector<glm::vec3> nan = sheet;
  nan[3].z = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_AS(NonrigidIcp(facerig::test::MeshOf(sheet, triangles), facerig::test::MeshOf(nan, triangles), {}), InvalidInputError);
  RegistrationLandmarks landmarks;
  landmarks.template_vertices = {0, 1, 99};
  landmarks.target_points = {sheet[0], sheet[1], sheet[2]};
  CHECK_THROWS_AS(NonrigidIcp(facerig::test::MeshOf(sheet, triangles), facerig::test::MeshOf(sheet, triangles), landmarks), InvalidInputError);
  landmarks.template_vertices = {0, 1};
  CHECK_THROWS_AS(NonrigidIcp(facerig::test::MeshOf(sheet, triangles), facerig::test::MeshOf(sheet, triangles), landmarks), InvalidInputError);
  NonrigidIcpParams params;
  params.stiffness.clear();
  CHECK_THROWS_AS(NonrigidIcp(facerig::test::MeshOf(sheet, triangles), facerig::test::MeshOf(sheet, triangles), {}, params), InvalidInputError);
}

// With `detect`, the target's landmarks come from the automatic detector
// (the full pipeline), otherwise from the ground truth.
void RunIctFit(bool remesh, std::uint32_t seed, double units_per_cm, bool detect) {
  const test::IctFaceModel& ict = test::IctFaces();
  test::RegistrationTargetOptions options;
  options.seed = seed;
  options.remesh = remesh;
  options.units_per_cm = units_per_cm;
  const test::RegistrationTarget target = test::MakeRegistrationTarget(options);
  NonrigidIcpParams params;
  params.region_vertex_count = test::IctFaces().head_vertex_count();
  RegistrationLandmarks landmarks = IctLandmarks(target);
  if (detect) {
    LandmarkDetector detector;
    const LandmarkResult detected = detector.Detect(target.mesh());
    landmarks.target_points = detected.landmarks.points;
    landmarks.confidence = detected.landmarks.confidence;
  }
  const NonrigidIcpResult fit =
      NonrigidIcp(ict.mesh(), target.mesh(), landmarks, params);
  const FitReport report = Measure(fit, target);
  std::printf(
      "nicp %s seed %u (%s landmarks): target %zu vertices, rotation %.1f deg, %.2f units/cm: correspondence mean %.3f cm "
      "p95 %.3f cm; residual mean %.4f%% p95 %.4f%% max %.3f%% (%zu measured, %zu rejected); landmark rms "
      "%.3f cm; %d factorizations; %.2f s (rigid %.2f, setup %.2f, closest %.2f, factorize %.2f, solve %.2f)\n",
      remesh ? "re-meshed" : "same-topology", seed, detect ? "detected" : "true", target.positions.size(), target.rotation_degrees,
      units_per_cm, report.correspondence_mean_cm, report.correspondence_p95_cm, fit.residual.mean_percent,
      fit.residual.p95_percent, fit.residual.max_percent, fit.residual.vertex_count,
      fit.residual.rejected_count, fit.landmark_rms / units_per_cm, fit.factorizations, fit.timings.total_seconds,
      fit.timings.rigid_seconds, fit.timings.setup_seconds, fit.timings.correspondence_seconds,
      fit.timings.factorize_seconds, fit.timings.solve_seconds);
  CHECK(report.correspondence_mean_cm <= 0.25);
  CHECK(fit.residual.mean_percent <= 0.1);
  CHECK(fit.residual.p95_percent <= 0.5);
  // Inner parts moved with the face: eyeballs stay near their true place.
  double eye_error = 0.0;
  for (std::uint32_t v = 21451; v < 24591; ++v) {
    eye_error += static_cast<double>(glm::length(fit.positions[v] - target.true_ict_positions[v]));
  }
  eye_error /= 3140.0 * units_per_cm;
  std::printf("  eyeball vertices: mean error %.3f cm\n", eye_error);
  CHECK(eye_error < 0.5);
}

TEST_CASE("Non-rigid ICP registers ICT onto a random ICT face (shared data)", "[nonrigid_icp][shared-data][accuracy]") {
  RunIctFit(false, 21, 1.0, false);
}

TEST_CASE("Non-rigid ICP registers ICT onto a re-meshed random face in metres, detected landmarks (shared data)",
          "[nonrigid_icp][shared-data][accuracy]") {
  RunIctFit(true, 22, 0.01, true);
}

}  // namespace
}  // namespace facerig

namespace facerig {
namespace {

TEST_CASE("Landmarks and registration on a non-manifold re-meshed ICT face with stray points (shared data)",
          "[nonrigid_icp][landmarks][shared-data]") {
  const test::IctFaceModel& ict = test::IctFaces();
  test::RegistrationTargetOptions options;
  options.seed = 23;
  options.units_per_cm = 10.0;
  test::RegistrationTarget target = test::MakeRegistrationTarget(options);
  const std::size_t added = AddNonManifoldDefects(target.positions, target.triangles, 400, 0.003f);
  LandmarkDetector detector;
  const LandmarkResult detected = detector.Detect(target.mesh());
  const double interocular = static_cast<double>(glm::length(target.true_landmarks[36] - target.true_landmarks[45]));
  double landmark_error = 0.0;
  for (std::size_t k = 17; k < 68; ++k) {
    landmark_error +=
        static_cast<double>(glm::length(detected.landmarks.points[k] - target.true_landmarks[k])) / interocular / 51.0;
  }
  NonrigidIcpParams params;
  params.region_vertex_count = test::IctFaces().head_vertex_count();
  RegistrationLandmarks landmarks = IctLandmarks(target);
  landmarks.target_points = detected.landmarks.points;
  landmarks.confidence = detected.landmarks.confidence;
  const NonrigidIcpResult fit =
      NonrigidIcp(ict.mesh(), target.mesh(), landmarks, params);
  const FitReport report = Measure(fit, target);
  std::printf("non-manifold target (%zu defect triangles, 21 stray vertices): landmark error/IOD %.4f without jaw; "
              "correspondence mean %.3f cm, residual mean %.4f%% p95 %.4f%%; %.2f s\n",
              added, landmark_error, report.correspondence_mean_cm, fit.residual.mean_percent,
              fit.residual.p95_percent, fit.timings.total_seconds);
  CHECK(landmark_error < 0.04);
  CHECK(report.correspondence_mean_cm <= 0.3);
  CHECK(fit.residual.mean_percent <= 0.1);
  CHECK(fit.residual.p95_percent <= 0.5);
}

}  // namespace
}  // namespace facerig
