#include "facerig/offline/registration/rigid_align.h"

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/geometry/closest_point.h"
#include "facerig/offline/registration/nonrigid_icp.h"
#include "facerig/offline/error.h"
#include "support/ict_faces.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

SimilarityTransform MakeTransform(double scale, double degrees, Eigen::Vector3d axis, Eigen::Vector3d t) {
  SimilarityTransform transform;
  transform.scale = scale;
  transform.rotation = Eigen::AngleAxisd(degrees * 3.14159265358979323846 / 180.0, axis.normalized())
                           .toRotationMatrix();
  transform.translation = t;
  return transform;
}

double RotationErrorDegrees(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  const Eigen::AngleAxisd difference(a.transpose() * b);
  return std::abs(difference.angle()) * 180.0 / 3.14159265358979323846;
}

// A closed, bumpy sphere-like surface (a UV sphere with a nose): not symmetric
// enough for ICP to slide.
void MakeBumpySphere(std::vector<glm::vec3>& positions, std::vector<Triangle>& triangles) {
  const auto bumpy = [](double theta, double phi) {
    glm::vec3 d(static_cast<float>(std::sin(theta) * std::cos(phi)), static_cast<float>(std::cos(theta)),
                static_cast<float>(std::sin(theta) * std::sin(phi)));
    const float bump = 1.0f + 0.25f * std::exp(-12.0f * glm::dot(d - glm::vec3(0, 0, 1), d - glm::vec3(0, 0, 1))) +
                       0.08f * d.x * d.y + 0.1f * d.y * d.y * d.y;
    return glm::vec3(1.0f, 1.3f, 0.9f) * d * bump;
  };
  test::MakeUvSphere(40, 60, bumpy, positions, triangles);
}

TEST_CASE("Umeyama recovers an exact similarity, including a scale of 100", "[rigid_align]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<glm::vec3> source(68);
  for (glm::vec3& p : source) p = {u(rng) * 8.0f, u(rng) * 10.0f, u(rng) * 5.0f};
  for (double scale : {100.0, 0.01, 1.0}) {
    const SimilarityTransform truth = MakeTransform(scale, 23.0, {1, 2, -0.5}, {3.0, -40.0, 7.5});
    std::vector<glm::vec3> target;
    for (const glm::vec3& p : source) target.push_back(truth.Apply(p));
    const SimilarityTransform fit = Umeyama(source, target);
    CHECK(fit.scale == Approx(scale).epsilon(1e-5));
    CHECK(RotationErrorDegrees(fit.rotation, truth.rotation) < 1e-3);
    CHECK((fit.translation - truth.translation).norm() < 1e-4 * std::max(1.0, scale) * 50.0);
    for (std::size_t i = 0; i < source.size(); ++i) {
      CHECK(glm::length(fit.Apply(source[i]) - target[i]) < 1e-4f * static_cast<float>(std::max(1.0, scale)) * 10.0f);
    }
    // Inverse and composition.
    const SimilarityTransform round_trip = fit.Inverse() * fit;
    CHECK(round_trip.scale == Approx(1.0));
    CHECK((round_trip.rotation - Eigen::Matrix3d::Identity()).norm() < 1e-9);
  }
  // Rigid only: the scale stays 1.
  const SimilarityTransform rigid_truth = MakeTransform(1.0, -12.0, {0, 1, 0}, {1, 2, 3});
  std::vector<glm::vec3> target;
  for (const glm::vec3& p : source) target.push_back(rigid_truth.Apply(p));
  CHECK(Umeyama(source, target, {}, false).scale == 1.0);
}

TEST_CASE("Umeyama rejects invalid input", "[rigid_align]") {
  const std::vector<glm::vec3> three{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<glm::vec3> two{{0, 0, 0}, {1, 0, 0}};
  CHECK_THROWS_AS(Umeyama(three, two), InvalidInputError);
  CHECK_THROWS_AS(Umeyama(two, two), InvalidInputError);
  const std::vector<glm::vec3> same{{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  CHECK_THROWS_AS(Umeyama(same, three), InvalidInputError);
  std::vector<glm::vec3> nan = three;
  nan[1].y = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_AS(Umeyama(nan, three), InvalidInputError);
}

TEST_CASE("Closest point on a mesh matches brute force", "[rigid_align]") {
  std::vector<glm::vec3> positions;
  std::vector<Triangle> triangles;
  MakeBumpySphere(positions, triangles);
  const ClosestPointQuery query(facerig::test::MeshOf(positions, triangles));
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  for (int i = 0; i < 200; ++i) {
    const glm::vec3 p(u(rng), u(rng), u(rng));
    float best = std::numeric_limits<float>::infinity();
    for (const Triangle& t : triangles) {
      glm::vec3 b;
      const glm::vec3 q = ClosestPointOnTriangle(p, positions[t[0]], positions[t[1]], positions[t[2]], b);
      best = std::min(best, glm::length(q - p));
    }
    const ClosestPointHit hit = query.Find(p);
    REQUIRE(hit.triangle >= 0);
    CHECK(hit.distance == Approx(best).margin(1e-5));
    const Triangle& t = triangles[static_cast<std::size_t>(hit.triangle)];
    const glm::vec3 from_bary = hit.barycentrics.x * positions[t[0]] + hit.barycentrics.y * positions[t[1]] +
                                hit.barycentrics.z * positions[t[2]];
    CHECK(glm::length(from_bary - hit.point) < 1e-5f);
  }
  // Radius limit.
  CHECK(query.Find({0, 0, 10}, 1.0f).triangle == -1);
  // Boundary: an open square.
  const std::vector<glm::vec3> square{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<Triangle> two{{0, 1, 2}, {0, 2, 3}};
  const ClosestPointQuery open(facerig::test::MeshOf(square, two));
  CHECK(open.Find({2, 0.5f, 0}).on_boundary);
  CHECK_FALSE(open.Find({0.5f, 0.5f, 1}).on_boundary);
  CHECK_THROWS_AS(ClosestPointQuery(facerig::test::MeshOf({}, {})), InvalidInputError);
}

TEST_CASE("Point-to-plane ICP converges from a 25 degree start at scale 100", "[rigid_align]") {
  std::vector<glm::vec3> positions;
  std::vector<Triangle> triangles;
  MakeBumpySphere(positions, triangles);
  for (const Eigen::Vector3d& axis : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0),
                                      Eigen::Vector3d(0.3, -0.5, 1), Eigen::Vector3d(-1, 1, 0)}) {
    for (double scale : {100.0, 0.01}) {
      const SimilarityTransform truth = MakeTransform(scale, 25.0, axis, Eigen::Vector3d(2, -1, 3) * scale);
      std::vector<glm::vec3> target;
      for (const glm::vec3& p : positions) target.push_back(truth.Apply(p));
      // No landmarks: the start is centroids and RMS radii, 25 degrees off.
      const RigidAlignResult result = RigidAlign(facerig::test::MeshOf(positions, triangles), facerig::test::MeshOf(target, triangles));
      INFO("axis " << axis.transpose() << " scale " << scale << " iterations " << result.iterations);
      CHECK(RotationErrorDegrees(result.transform.rotation, truth.rotation) < 0.2);
      CHECK(result.transform.scale == Approx(scale).epsilon(2e-3));
      CHECK(result.rms_final < 2e-3 * scale);
    }
  }
}

TEST_CASE("Rigid alignment rejects bad meshes", "[rigid_align]") {
  std::vector<glm::vec3> positions;
  std::vector<Triangle> triangles;
  MakeBumpySphere(positions, triangles);
  CHECK_THROWS_AS(RigidAlign(facerig::test::MeshOf({}, {}), facerig::test::MeshOf(positions, triangles)), InvalidInputError);
  std::vector<glm::vec3> nan = positions;
  nan[10].x = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_AS(RigidAlign(facerig::test::MeshOf(nan, triangles), facerig::test::MeshOf(positions, triangles)), InvalidInputError);
  std::vector<Triangle> bad = triangles;
  bad[3][1] = 1u << 30;
  CHECK_THROWS_AS(RigidAlign(facerig::test::MeshOf(positions, bad), facerig::test::MeshOf(positions, triangles)), InvalidInputError);
  const std::vector<glm::vec3> three(3, glm::vec3(0.0f));
  CHECK_THROWS_AS(RigidAlign(facerig::test::MeshOf(positions, triangles), facerig::test::MeshOf(positions, triangles), three, {}), InvalidInputError);
}

TEST_CASE("Rigid alignment of the ICT face onto a re-meshed random face (shared data)",
          "[rigid_align][shared-data]") {
  const test::IctFaceModel& ict = test::IctFaces();
  for (std::uint32_t seed : {11u, 12u}) {
    test::RegistrationTargetOptions options;
    options.seed = seed;
    options.units_per_cm = seed == 11u ? 0.01 : 10.0;  // metres and millimetres
    const test::RegistrationTarget target = test::MakeRegistrationTarget(options);
    std::vector<glm::vec3> template_landmarks;
    for (std::uint32_t v : ict.info.landmark_vertices) template_landmarks.push_back(ict.neutral[v]);
    const RigidAlignResult result = RigidAlign(ict.head_mesh(), target.mesh(), template_landmarks, target.true_landmarks);
    INFO("seed " << seed << " rotation " << target.rotation_degrees << " iterations " << result.iterations);
    // A random identity is not a similar copy of the neutral: a few degrees and
    // percent of slack; the landmarks end up within a centimetre.
    CHECK(RotationErrorDegrees(result.transform.rotation, target.from_ict.rotation) < 5.0);
    CHECK(result.transform.scale == Approx(target.units_per_cm).epsilon(0.15));
    CHECK(result.landmark_rms < 1.0 * target.units_per_cm);
  }
}

}  // namespace
}  // namespace facerig
