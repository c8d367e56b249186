// The default head's short hair: one hairline (by azimuth about the vertical
// axis) shared by the sculpt, which lifts the scalp under the hair by a few
// millimetres so the hair has a little volume and a ridge at its edge, and by
// the painted texture (strands combed away from the crown, darker and lighter
// clumps, a soft sheen, a wispy hairline).
#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <opencv2/imgproc.hpp>

#include "default_head/albedo.h"
#include "geometry/piecewise_linear.h"

namespace facerig::default_head {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kHairThickness = 0.3;  // cm at full volume

// Height (cm) of the hairline by azimuth about the vertical axis (degrees
// from the front): high on the forehead, down in front of the ears as
// sideburns, over the ears, down to the nape.
double HairlineHeight(double azimuth_degrees) {
  static constexpr double kLine[][2] = {{0, 7.6},   {20, 7.3},  {40, 6.2},  {55, 4.6},  {68, 3.0},
                                        {78, 0.5},  {85, -1.2}, {90, 0.8},  {97, 2.0},  {108, 1.2},
                                        {125, -3.0}, {150, -6.5}, {180, -7.5}};
  return PiecewiseLinear(kLine, std::min(std::abs(azimuth_degrees), 180.0));
}

// Height above the hairline (cm, negative below) and 0 on the ears, 1 away from them.
struct HairPlace {
  double above, off_ear;
};
HairPlace PlaceOnScalp(const glm::dvec3& p) {
  const glm::dvec3 origin = SurfaceOrigin();
  const double azimuth = std::atan2(p.x, p.z - origin.z) * 180.0 / kPi;
  const glm::dvec3 ear = (glm::dvec3(std::abs(p.x), p.y, p.z) - glm::dvec3(7.4, -1.3, -1.2)) / glm::dvec3(1.6, 3.0, 2.0);
  return {p.y - HairlineHeight(azimuth), std::clamp((glm::length(ear) - 1.0) / 0.3, 0.0, 1.0)};
}

// How much hair covers a skin point: 1 above the hairline, 0 below it and on the ears.
float HairCoverage(const cv::Vec3f& p) {
  const HairPlace place = PlaceOnScalp({p[0], p[1], p[2]});
  return static_cast<float>(std::clamp(0.5 + place.above / 0.6, 0.0, 1.0) * place.off_ear);
}

// Strokes running away from the crown (the centre of the UV disc), so they
// comb down the head whichever side they are on; `count` strokes of the
// given thickness and length range (fractions of the texture), on grey.
cv::Mat CombedStrokes(int size, int count, int thickness, double min_length, double max_length, std::uint64_t seed) {
  cv::Mat strokes(size, size, CV_8U, cv::Scalar::all(110));
  cv::RNG rng(seed);
  const cv::Point2f centre(0.5f * static_cast<float>(size), 0.5f * static_cast<float>(size));
  for (int i = 0; i < count; ++i) {
    const double angle = rng.uniform(0.0, 2.0 * kPi);
    const double from = rng.uniform(0.0, 0.36) * size, length = rng.uniform(min_length, max_length) * size;
    const cv::Point2f dir(static_cast<float>(std::sin(angle)), static_cast<float>(std::cos(angle)));
    const cv::Point2f a = centre + dir * static_cast<float>(from), b = centre + dir * static_cast<float>(from + length);
    cv::line(strokes, a, b, cv::Scalar(rng.uniform(40, 255)), thickness, cv::LINE_AA);
  }
  cv::Mat result;
  strokes.convertTo(result, CV_32F, 1.0 / 255.0);
  return result;
}

}  // namespace

double HairThickness(const glm::dvec3& p) {
  const HairPlace place = PlaceOnScalp(p);
  const double t = std::clamp((place.above + 0.1) / 0.6, 0.0, 1.0);
  return kHairThickness * t * t * (3.0 - 2.0 * t) * place.off_ear;
}

void PaintHair(SkinCanvas& canvas) {
  const cv::Mat strands = CombedStrokes(canvas.size, 14000, 1, 0.015, 0.05, 31);
  cv::Mat clumps = CombedStrokes(canvas.size, 1600, 4, 0.03, 0.08, 32);
  cv::GaussianBlur(clumps, clumps, cv::Size(0, 0), 1.5);
  const cv::Vec3f dark = Bgr(0.16f, 0.10f, 0.07f), light = Bgr(0.38f, 0.27f, 0.18f);
  for (int y = 0; y < canvas.size; ++y) {
    for (int x = 0; x < canvas.size; ++x) {
      if (!canvas.covered.at<std::uint8_t>(y, x)) continue;
      const cv::Vec3f p = canvas.position.at<cv::Vec3f>(y, x);
      const float cover = HairCoverage(p);
      if (cover <= 0.0f) continue;
      const float strand = strands.at<float>(y, x);
      // A wispy hairline: near the edge, strands decide.
      const float edge = 4.0f * cover * (1.0f - cover);
      const float a = std::clamp(cover + (strand - 0.45f) * 1.2f * edge, 0.0f, 1.0f);
      // Clumps of lighter and darker hair, and a soft sheen across the top of the head.
      const float clump = 0.75f + 0.55f * clumps.at<float>(y, x);
      const float sheen = 1.0f + 0.22f * static_cast<float>(std::exp(-std::pow((p[1] - 9.0) / 1.6, 2.0)));
      const cv::Vec3f hair = (dark * (1.0f - strand) + light * strand) * (clump * sheen);
      cv::Vec3f& c = canvas.colour.at<cv::Vec3f>(y, x);
      c = c * (1.0f - a) + hair * a;
    }
  }
}

}  // namespace facerig::default_head
