#include "facerig/offline/openings/gaps.h"
#include "facerig/offline/landmarks/landmarks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/default_head/default_head.h"
#include "facerig/offline/transfer/deformation_transfer.h"
#include "facerig/offline/error.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/io/obj.h"
#include "support/ict_faces.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

LandmarkDetector& Detector() {
  static LandmarkDetector detector;  // the model loads once per test binary
  return detector;
}

void MakeBlob(std::vector<glm::vec3>& positions, std::vector<Triangle>& triangles) {
  test::MakeUvSphere(
      30, 40,
      [](double theta, double phi) {
        return glm::vec3(static_cast<float>(std::sin(theta) * std::cos(phi)), static_cast<float>(1.2 * std::cos(theta)),
                         static_cast<float>(0.8 * std::sin(theta) * std::sin(phi)));
      },
      positions, triangles);
}

TEST_CASE("Landmark JSON round trip and malformed files", "[landmarks]") {
  FaceLandmarks landmarks;
  for (std::uint32_t i = 0; i < 68; ++i) {
    landmarks.points.push_back({0.5f * static_cast<float>(i), -1.25f, 3.0f});
    landmarks.confidence.push_back(i < 17 ? 0.3f : 1.0f);
    landmarks.indices.push_back(i);
  }
  const auto path = test::OutputPath("landmarks_round_trip.json");
  WriteLandmarksJson(path, landmarks);
  const FaceLandmarks read = ReadLandmarksJson(path);
  REQUIRE(read.points.size() == 68);
  CHECK(read.points[10] == landmarks.points[10]);
  CHECK(read.confidence[3] == Approx(0.3f));
  CHECK(read.indices[67] == 67);

  // A manual file: a handful of points with their dlib indices, no confidences.
  const auto manual = test::OutputPath("landmarks_manual.json");
  std::ofstream(manual) << R"({"points": [[0,1,2],[1,1,2],[2,1,2]], "indices": [30, 36, 45]})";
  const FaceLandmarks few = ReadLandmarksJson(manual);
  CHECK(few.points.size() == 3);
  CHECK(few.indices[1] == 36);
  CHECK(few.confidence[2] == 1.0f);

  const auto bad = test::OutputPath("landmarks_bad.json");
  std::ofstream(bad) << R"({"points": [[0,1],[1,1,2]]})";
  CHECK_THROWS_AS(ReadLandmarksJson(bad), IoError);
  std::ofstream(bad) << R"({"points": [[0,1,2]], "indices": [68]})";
  CHECK_THROWS_AS(ReadLandmarksJson(bad), IoError);
  std::ofstream(bad) << "not json";
  CHECK_THROWS_AS(ReadLandmarksJson(bad), IoError);
  CHECK_THROWS_AS(ReadLandmarksJson(test::OutputPath("does_not_exist.json")), IoError);
}

TEST_CASE("Landmarks: bad input gives typed errors", "[landmarks]") {
  CHECK_THROWS_AS(Detector().Detect(facerig::test::MeshOf({}, {})), InvalidInputError);
  std::vector<glm::vec3> positions;
  std::vector<Triangle> triangles;
  MakeBlob(positions, triangles);
  std::vector<glm::vec3> nan = positions;
  nan[5].x = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_AS(Detector().Detect(facerig::test::MeshOf(nan, triangles)), InvalidInputError);
  // A mesh with no face: the error suggests a landmark file.
  try {
    (void)Detector().Detect(facerig::test::MeshOf(positions, triangles));
    FAIL("a blob has no face");
  } catch (const LandmarkDetectionError& e) {
    CHECK(std::string(e.what()).find("--landmarks") != std::string::npos);
  }
  LandmarkParams params;
  params.shape_predictor = test::OutputPath("no_such_model.dat");
  CHECK_THROWS_AS(LandmarkDetector(params), IoError);
}

TEST_CASE("Landmarks on random re-meshed ICT faces (shared data)", "[landmarks][shared-data][accuracy]") {
  LandmarkDetector& detector = Detector();
  LandmarkParams plain_params;
  plain_params.fit_eyes_to_openings = false;
  LandmarkDetector plain_detector(plain_params);
  LandmarkParams pca_params = plain_params;
  pca_params.correct_eye_corners = true;
  LandmarkDetector pca_detector(pca_params);
  double corner_error = 0.0, pca_corner_error = 0.0;
  double eye_error = 0.0, plain_eye_error = 0.0;  // the 12 eye points
  int corners_moved = 0, eyes_fitted = 0;
  double sum_no_jaw = 0.0, sum_all = 0.0, seconds = 0.0;
  int faces = 0;
  std::vector<double> per_landmark(68, 0.0);
  for (std::uint32_t seed : {31u, 32u, 33u, 34u, 35u}) {
    test::RegistrationTargetOptions options;
    options.seed = seed;
    const test::RegistrationTarget target = test::MakeRegistrationTarget(options);
    const LandmarkResult result = detector.Detect(target.mesh());
    if (seed == 31u) {
      WritePng(test::OutputPath("landmarks_debug_31.png"), DrawLandmarks(result));
      // The target itself, for trying the command-line tools by hand.
      const Part part{"skin", 0, static_cast<std::uint32_t>(target.triangles.size()), 0,
                      static_cast<std::uint32_t>(target.positions.size())};
      WriteObj(test::OutputPath("registration_target_31.obj"), target.positions, {}, {}, target.triangles,
               std::span<const Part>(&part, 1));
    }
    REQUIRE(result.landmarks.points.size() == 68);
    const double interocular = static_cast<double>(glm::length(target.true_landmarks[36] - target.true_landmarks[45]));
    // The eye-corner PCA correction (the automatic-correspondence paper, 3.3) and the eyes fitted to
    // the openings (the default), measured against the plain detection.
    const LandmarkResult plain = plain_detector.Detect(target.mesh());
    const LandmarkResult pca = pca_detector.Detect(target.mesh());
    corners_moved += pca.corrected;
    eyes_fitted += result.eyes_fitted;
    for (std::size_t k = 36; k < 48; ++k) {
      eye_error += static_cast<double>(glm::length(result.landmarks.points[k] - target.true_landmarks[k])) /
                   interocular / 12.0;
      plain_eye_error += static_cast<double>(glm::length(plain.landmarks.points[k] - target.true_landmarks[k])) /
                         interocular / 12.0;
    }
    for (std::size_t k : {36, 39, 42, 45}) {
      corner_error += static_cast<double>(glm::length(plain.landmarks.points[k] - target.true_landmarks[k])) /
                      interocular / 4.0;
      pca_corner_error += static_cast<double>(glm::length(pca.landmarks.points[k] - target.true_landmarks[k])) /
                          interocular / 4.0;
    }
    double no_jaw = 0.0, all = 0.0;
    for (std::size_t k = 0; k < 68; ++k) {
      const double error =
          static_cast<double>(glm::length(result.landmarks.points[k] - target.true_landmarks[k])) / interocular;
      per_landmark[k] += error;
      all += error;
      if (k >= 17) no_jaw += error;
    }
    no_jaw /= 51.0;
    all /= 68.0;
    std::printf("landmarks seed %u (rotation %.1f deg, %.2f units/cm, %zu vertices): error/IOD %.4f without jaw, "
                "%.4f with; %d views, %d snapped, score %.2f, %.3f s\n",
                seed, target.rotation_degrees, target.units_per_cm, target.positions.size(), no_jaw, all,
                result.views_tried, result.snapped, result.detector_score, result.seconds);
    sum_no_jaw += no_jaw;
    sum_all += all;
    seconds += result.seconds;
    ++faces;
  }
  std::printf("landmarks: mean error/IOD %.4f without jaw, %.4f with; %.3f s per face; eye points %.4f, "
              "without fitting them to the openings %.4f (%d eyes fitted); eye corners without fitting %.4f, "
              "with the PCA correction %.4f (%d corners moved)\n  per landmark:",
              sum_no_jaw / faces, sum_all / faces, seconds / faces, eye_error / faces, plain_eye_error / faces,
              eyes_fitted, corner_error / faces, pca_corner_error / faces, corners_moved);
  for (std::size_t k = 0; k < 68; ++k) std::printf(" %zu:%.3f", k, per_landmark[k] / faces);
  std::printf("\n");
  // Issue 5: <= 0.03 of the inter-ocular distance without the jaw, <= 0.06 with it.
  CHECK(sum_no_jaw / faces <= 0.03);
  CHECK(sum_all / faces <= 0.06);
  // The PCA correction finds the eye openings of these meshes; on ICT it does
  // not beat the calibrated detection (the ICT corner vertices are not the
  // openings' extremes), hence off by default.
  CHECK(corners_moved > 0);
  CHECK(pca_corner_error / faces < 0.04);
}

// The built-in head is stylized: dlib, trained on photographs, misses its
// eyes (2.8 cm wide against 2.1, the upper lids on the brows). Its eyes are
// holes in the skin, so the eye points go onto their margins.
TEST_CASE("Landmarks on the built-in stylized head: eyes fitted to its eye openings", "[landmarks]") {
  const Rig head = BuildDefaultHead();
  const std::vector<std::vector<glm::vec3>> expressions = RigExpressionMeshes(head);
  LandmarkParams plain_params;
  plain_params.fit_eyes_to_openings = false;
  const LandmarkResult plain = LandmarkDetector(plain_params).Detect(facerig::NeutralMesh(head));
  const LandmarkResult fitted = Detector().Detect(facerig::NeutralMesh(head));
  CHECK(fitted.eyes_fitted == 2);
  // The head's own lid margins, from its blinks; the eye points' distances to them over the eye width.
  for (const auto& [blink, first] : {std::pair<const char*, std::size_t>{"eyeBlink_R", 36}, {"eyeBlink_L", 42}}) {
    const OpeningMargins lids = FindEyelidMargins(facerig::NeutralMesh(head), expressions[*head.FindShape(blink)], 0, head.vertex_count());
    auto off_margin = [&](glm::vec3 p, const std::vector<std::uint32_t>& margin) {
      float nearest = std::numeric_limits<float>::max();
      for (std::uint32_t v : margin) nearest = std::min(nearest, glm::length(head.positions()[v] - p));
      return static_cast<double>(nearest) / lids.width;
    };
    for (std::size_t k : {first + 1, first + 2}) {
      INFO(blink << " landmark " << k);
      CHECK(off_margin(fitted.landmarks.points[k], lids.upper) < 0.05);
      CHECK(off_margin(plain.landmarks.points[k], lids.upper) > 0.2);
    }
    for (std::size_t k : {first + 4, first + 5}) {
      INFO(blink << " landmark " << k);
      CHECK(off_margin(fitted.landmarks.points[k], lids.lower_margin) < 0.05);
      CHECK(off_margin(plain.landmarks.points[k], lids.lower_margin) > 0.2);
    }
  }
}

// A scan-sized mesh takes the clustered front-view estimate
// (LandmarkParams::proxy_triangle_limit); the landmarks stay as accurate.
TEST_CASE("Landmarks on a 400k-vertex re-meshed ICT face (shared data)", "[landmarks][shared-data]") {
  test::RegistrationTargetOptions options;
  options.seed = 36;
  options.target_vertex_count = 400000;
  const test::RegistrationTarget target = test::MakeRegistrationTarget(options);
  REQUIRE(target.positions.size() == 400000);
  REQUIRE(target.triangles.size() > Detector().params().proxy_triangle_limit);
  const LandmarkResult result = Detector().Detect(target.mesh());
  const double interocular = static_cast<double>(glm::length(target.true_landmarks[36] - target.true_landmarks[45]));
  double no_jaw = 0.0;
  for (std::size_t k = 17; k < 68; ++k) {
    no_jaw += static_cast<double>(glm::length(result.landmarks.points[k] - target.true_landmarks[k])) / interocular / 51.0;
  }
  std::printf("landmarks on %zu vertices, %zu triangles: error/IOD %.4f without jaw; %d views; %.3f s\n",
              target.positions.size(), target.triangles.size(), no_jaw, result.views_tried, result.seconds);
  CHECK(no_jaw < 0.04);
}

}  // namespace
}  // namespace facerig

namespace facerig {
namespace {

// Prints the calibration table of offline/src/landmark_calibration.inc
// (hidden: run with "[.calibrate]" by hand).
TEST_CASE("Landmarks: measure dlib's offsets against the ICT landmark vertices (shared data)",
          "[.calibrate][shared-data]") {
  LandmarkParams params;
  params.calibrate = false;
  LandmarkDetector detector(params);
  std::vector<glm::vec2> sum(68, glm::vec2(0.0f));
  int faces = 0;
  for (std::uint32_t seed = 101; seed <= 112; ++seed) {
    test::RegistrationTargetOptions options;
    options.seed = seed;
    const test::RegistrationTarget target = test::MakeRegistrationTarget(options);
    const LandmarkResult result = detector.Detect(target.mesh());
    const float box = 0.5f * static_cast<float>(params.landmark_image_size);
    for (std::size_t k = 0; k < 68; ++k) {
      const glm::vec3 truth = ProjectToImage(result.view, target.true_landmarks[k]);
      sum[k] += (result.detected_pixels[k] - glm::vec2(truth.x, truth.y)) / box;
    }
    ++faces;
  }
  for (std::size_t k = 0; k < 68; ++k) {
    std::printf("{%.4ff, %.4ff},  // %zu\n", sum[k].x / static_cast<float>(faces),
                sum[k].y / static_cast<float>(faces), k);
  }
}

}  // namespace
}  // namespace facerig
