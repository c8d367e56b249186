// The photo's two face detectors: dlib's HOG detector and, where it finds
// nothing, OpenCV's Haar cascade with its box moved to dlib's (face_cascade.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/error.h"
#include "facerig/offline/photo/face_cascade.h"
#include "facerig/offline/photo/image.h"
#include "facerig/offline/photo/landmarks.h"
#include "facerig/runtime/behaviour/blink.h"
#include "facerig/runtime/error.h"
#include "offline/photo/photo_renders.h"
#include "support/test_meshes.h"

namespace {

using facerig::ImageFaceBox;
using facerig::RgbImage;
using facerig::test::kPi;
using facerig::test::RenderStyle;

// A light from the subject's side (degrees from the view axis, from the left)
// and a little above, with little ambient light.
RenderStyle LightFromSide(float degrees, float ambient) {
  const float off = degrees * kPi / 180.0f;
  return {.light = glm::normalize(glm::vec3(-std::sin(off), 0.25f, std::cos(off))), .ambient = ambient};
}

glm::vec2 Centre(const ImageFaceBox& box) {
  return {0.5f * float(box.left + box.right), 0.5f * float(box.top + box.bottom)};
}

// Mean distance between two sets of 68 points, as a fraction of the distance
// between the eyes' centres in `reference`.
double PointError(const std::vector<glm::vec2>& points, const std::vector<glm::vec2>& reference) {
  glm::vec2 right(0.0f), left(0.0f);
  for (std::size_t k = 36; k < 42; ++k) right += reference[k] / 6.0f;
  for (std::size_t k = 42; k < 48; ++k) left += reference[k] / 6.0f;
  double sum = 0.0;
  for (std::size_t k = 0; k < 68; ++k) sum += glm::length(points[k] - reference[k]);
  return sum / 68.0 / double(glm::length(left - right));
}

struct Sample {
  RgbImage image;
  std::string name;
  std::vector<glm::vec2> truth;  // exact landmark projections (renders), else empty
};

std::vector<Sample> RenderSamples(int faces) {
  const facerig::test::IctPhotoSetup& setup = facerig::test::Setup();
  std::vector<Sample> samples;
  facerig::Pcg32 rng(31);
  const std::pair<const char*, RenderStyle> styles[] = {
      {"flat", RenderStyle{}}, {"side40", facerig::test::SideLight()}, {"hard", facerig::test::Hard()},
      {"side70", LightFromSide(70.0f, 0.05f)}, {"side85", LightFromSide(85.0f, 0.03f)}};
  for (int f = 0; f < faces; ++f) {
    std::vector<double> weights(setup.model.identity_modes.size());
    for (double& w : weights) w = rng.NextNormal();
    const std::vector<glm::vec3> face = facerig::test::FaceWithWeights(setup.model, weights);
    for (const float yaw : {-15.0f, 0.0f, 8.0f, 15.0f}) {
      for (const auto& [name, style] : styles) {
        samples.push_back({facerig::test::RenderFace(setup.info, face, yaw, 512, style),
                           std::string(name) + " yaw " + std::to_string(int(yaw)),
                           facerig::test::ExactLandmarks(setup.info, face, yaw, 512, 0.0f)});
      }
    }
  }
  return samples;
}

std::vector<Sample> PhotoSamples() {
  std::vector<std::filesystem::path> paths{std::filesystem::path(FACERIG_SAMPLE_PHOTOS_DIR) / "astronaut.png"};
  const std::filesystem::path dlib_faces = "/usr/share/doc/libdlib19.1/examples/faces";
  if (std::filesystem::is_directory(dlib_faces)) {
    for (const auto& entry : std::filesystem::directory_iterator(dlib_faces)) {
      if (entry.path().extension() == ".jpg") paths.push_back(entry.path());
    }
  }
  std::sort(paths.begin(), paths.end());
  std::vector<Sample> samples;
  for (const auto& path : paths) samples.push_back({facerig::ReadPhoto(path).image, path.filename().string(), {}});
  return samples;
}

}  // namespace

// How Haar's boxes differ from dlib's on faces both find (kHaarToDlibBox),
// and how far the 68 points placed from the corrected Haar box are from those
// placed from dlib's own box.
TEST_CASE("Haar and dlib face boxes compared (shared data)", "[.measure_cascade][shared-data]") {
  facerig::LandmarkDetector& detector = facerig::test::Detector();
  facerig::FaceCascade cascade(facerig::DefaultFaceCascadePath());
  std::vector<Sample> samples = RenderSamples(6);
  const std::size_t renders = samples.size();
  for (Sample& s : PhotoSamples()) samples.push_back(std::move(s));
  glm::dvec3 sum(0.0), sum_sq(0.0);
  int both = 0, dlib_only = 0, haar_only = 0, neither = 0;
  struct Pair {
    std::size_t sample;
    ImageFaceBox dlib, haar;
  };
  std::vector<Pair> pairs;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const std::vector<ImageFaceBox> d = detector.DetectFaceBoxes(samples[i].image);
    const std::vector<ImageFaceBox> h = cascade.DetectFaceBoxes(samples[i].image, 40);
    if (i < renders) {
      if (d.empty() && h.empty()) ++neither;
      if (d.empty() && !h.empty()) {
        ++haar_only;
        std::printf("haar only: %s\n", samples[i].name.c_str());
      }
      if (!d.empty() && h.empty()) ++dlib_only;
      if (d.empty() || h.empty()) continue;
    }
    for (const ImageFaceBox& a : d) {
      for (const ImageFaceBox& b : h) {
        const float w = float(b.width());
        const glm::vec2 offset = (Centre(a) - Centre(b)) / w;
        const float scale = float(a.width()) / w;
        if (glm::length(offset) > 0.3f || scale < 0.6f || scale > 1.6f) continue;  // another face
        pairs.push_back({i, a, b});
        const glm::dvec3 x(offset.x, offset.y, scale);
        sum += x;
        sum_sq += x * x;
        ++both;
      }
    }
  }
  const glm::dvec3 mean = sum / double(both);
  const glm::dvec3 sd = glm::sqrt(glm::max(sum_sq / double(both) - mean * mean, glm::dvec3(0.0)));
  std::printf("renders: %zu; both %d, dlib only %d, haar only %d, neither %d\n", renders, both, dlib_only, haar_only,
              neither);
  std::printf("dlib box from haar's: dx %+.4f (sd %.4f) dy %+.4f (sd %.4f) scale %.4f (sd %.4f), %d pairs\n", mean.x,
              sd.x, mean.y, sd.y, mean.z, sd.z, both);
  const facerig::HaarToDlibBox measured{float(mean.x), float(mean.y), float(mean.z)};
  // dlib's box about its own points.
  glm::dvec3 box_sum(0.0), box_sq(0.0);
  for (const Pair& p : pairs) {
    const std::vector<glm::vec2> points = detector.PredictLandmarks(samples[p.sample].image, p.dlib);
    glm::vec2 centroid(0.0f);
    for (const glm::vec2 q : points) centroid += q / 68.0f;
    float squared = 0.0f;
    for (const glm::vec2 q : points) squared += glm::dot(q - centroid, q - centroid) / 68.0f;
    const float spread = std::sqrt(squared);
    const glm::vec2 offset = (Centre(p.dlib) - centroid) / spread;
    const glm::dvec3 x(offset.x, offset.y, float(p.dlib.width()) / spread);
    box_sum += x;
    box_sq += x * x;
  }
  const glm::dvec3 box_mean = box_sum / double(pairs.size());
  const glm::dvec3 box_sd = glm::sqrt(glm::max(box_sq / double(pairs.size()) - box_mean * box_mean, glm::dvec3(0.0)));
  std::printf("dlib box about its points: dx %+.4f (sd %.4f) dy %+.4f (sd %.4f) scale %.4f (sd %.4f)\n", box_mean.x,
              box_sd.x, box_mean.y, box_sd.y, box_mean.z, box_sd.z);
  const facerig::PointsToDlibBox from_points{float(box_mean.x), float(box_mean.y), float(box_mean.z)};
  double refined_error = 0.0;
  double raw_error = 0.0, corrected_error = 0.0, dlib_truth = 0.0, haar_truth = 0.0;
  double worst = 0.0;
  int truths = 0;
  for (const Pair& p : pairs) {
    const RgbImage& image = samples[p.sample].image;
    const std::vector<glm::vec2> from_dlib = detector.PredictLandmarks(image, p.dlib);
    const std::vector<glm::vec2> from_raw = detector.PredictLandmarks(image, p.haar);
    const std::vector<glm::vec2> from_haar =
        detector.PredictLandmarks(image, facerig::DlibBoxFromHaar(p.haar, measured));
    raw_error += PointError(from_raw, from_dlib);
    const std::vector<glm::vec2> refined =
        detector.PredictLandmarks(image, facerig::DlibBoxFromPoints(from_haar, from_points));
    refined_error += PointError(refined, from_dlib);
    const double e = PointError(from_haar, from_dlib);
    corrected_error += e;
    worst = std::max(worst, e);
    if (!samples[p.sample].truth.empty()) {
      dlib_truth += PointError(from_dlib, samples[p.sample].truth);
      haar_truth += PointError(from_haar, samples[p.sample].truth);
      ++truths;
    }
  }
  const double n = double(pairs.size());
  std::printf("68 points against dlib's own box's, fraction of the eye distance: raw haar box %.4f, corrected %.4f "
              "(worst %.4f)\n",
              raw_error / n, corrected_error / n, worst);
  std::printf("refined once through the points' box: %.4f\n", refined_error / n);
  std::printf("against the exact projections (%d renders): from dlib's box %.4f, from the corrected haar box %.4f\n",
              truths, dlib_truth / truths, haar_truth / truths);
}

TEST_CASE("A Haar box is moved and scaled to dlib's", "[photo_landmarks]") {
  const ImageFaceBox haar{100, 200, 300, 400, 7.0};
  const ImageFaceBox same = facerig::DlibBoxFromHaar(haar, {0.0f, 0.0f, 1.0f});
  CHECK(same.left == 100);
  CHECK(same.bottom == 400);
  const ImageFaceBox moved = facerig::DlibBoxFromHaar(haar, {0.1f, 0.05f, 0.9f});
  CHECK(moved.width() == 180);
  CHECK(moved.height() == 180);
  CHECK(Centre(moved).x == Approx(220.0f));
  CHECK(Centre(moved).y == Approx(310.0f));
  CHECK(moved.score == 7.0);
}

TEST_CASE("A face cascade file that is missing or not a cascade is refused", "[photo_landmarks]") {
  CHECK_THROWS_AS(facerig::FaceCascade(facerig::test::OutputPath("no_such_cascade.xml")), facerig::IoError);
  const std::filesystem::path not_xml = facerig::test::OutputPath("not_a_cascade.xml");
  std::ofstream(not_xml) << "<opencv_storage><no_cascade/></opencv_storage>\n";
  CHECK_THROWS_AS(facerig::FaceCascade(not_xml), facerig::IoError);
}

// The face dlib's HOG detector misses: turned 15 degrees, lit from 85 degrees
// to its side. The Haar cascade finds it, and the 68 points placed from its
// corrected box are as close to the truth as those placed from the box dlib
// gives for the same face evenly lit (the shadow, not the box, costs accuracy).
TEST_CASE("A side-lit turned face dlib misses is found by the Haar cascade (shared data)",
          "[photo_landmarks][shared-data]") {
  const facerig::test::IctPhotoSetup& setup = facerig::test::Setup();
  facerig::Pcg32 rng(31);
  std::vector<double> weights(setup.model.identity_modes.size());
  for (double& w : weights) w = rng.NextNormal();
  const std::vector<glm::vec3> face = facerig::test::FaceWithWeights(setup.model, weights);
  const RgbImage photo = facerig::test::RenderFace(setup.info, face, 15.0f, 512, LightFromSide(85.0f, 0.03f));
  facerig::WritePng(facerig::test::OutputPath("photo_side_lit_haar.png"), photo);
  facerig::LandmarkDetector& detector = facerig::test::Detector();
  REQUIRE(detector.DetectFaceBoxes(photo).empty());
  facerig::PhotoLandmarkParams dlib_only;
  dlib_only.face_cascade.clear();
  CHECK_THROWS_AS(facerig::DetectPhotoLandmarks(detector, photo, dlib_only), facerig::LandmarkDetectionError);
  REQUIRE(!facerig::DefaultFaceCascadePath().empty());
  const facerig::PhotoLandmarks found = facerig::DetectPhotoLandmarks(detector, photo);
  CHECK(found.detector == "haar");
  REQUIRE(found.notes.size() == 1);
  CHECK(found.notes[0].find("Haar") != std::string::npos);
  REQUIRE(found.pixels.size() == 68);
  const std::vector<glm::vec2> truth = facerig::test::ExactLandmarks(setup.info, face, 15.0f, 512, 0.0f);
  const double error = PointError(found.pixels, truth);
  // dlib's box for the same face under the default light, where it finds it.
  const RgbImage lit = facerig::test::RenderFace(setup.info, face, 15.0f, 512);
  const facerig::PhotoLandmarks from_dlib = facerig::DetectPhotoLandmarks(detector, lit);
  CHECK(from_dlib.detector == "dlib");
  const double dlib_box_error = PointError(detector.PredictLandmarks(photo, from_dlib.box), truth);
  std::printf("side-lit face: 68 points from the Haar box %.4f of the eye distance from the truth, from dlib's box "
              "of the evenly lit render %.4f (evenly lit, dlib's box: %.4f)\n",
              error, dlib_box_error, PointError(from_dlib.pixels, truth));
  std::printf("haar-derived box %d %d %d %d, dlib's evenly lit %d %d %d %d\n", found.box.left, found.box.top,
              found.box.right, found.box.bottom, from_dlib.box.left, from_dlib.box.top, from_dlib.box.right,
              from_dlib.box.bottom);
  CHECK(error < 0.15);
  CHECK(error < 1.15 * dlib_box_error);
}
