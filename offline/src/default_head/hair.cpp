// The default head's hair: one hairline (by azimuth about the vertical axis)
// shared by the sculpt and the painted texture. The sculpt grows a shell over
// the scalp (default_head_surface.cpp): thin at the roots along the forehead
// and temples, rising to a centimetre and more over the crown, and ending with
// its thickness over the tops of the ears and at the nape, where hair hangs and
// ends rather than grows; the ears pass under it. The texture paints strands
// combed away from the crown, darker and lighter clumps, a soft sheen and a
// wispy hairline wherever the shell is the surface.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <opencv2/imgproc.hpp>

#include "default_head/albedo.h"
#include "geometry/piecewise_linear.h"
#include "geometry/value_noise.h"
#include "default_head/angles.h"

namespace facerig::default_head {
namespace {

// Height (cm) of the hairline by azimuth about the vertical axis (degrees
// from the front): a rounded forehead line, a little higher over the temples'
// corners, down in front of the ears as sideburns, over the tops of the ears,
// down to the nape.
double HairlineHeight(double azimuth_degrees) {
  static constexpr double kLine[][2] = {{0, 7.5},   {14, 7.45}, {26, 7.2},  {36, 6.9},  {48, 5.7},
                                        {60, 4.0},  {70, 2.4},  {78, 0.6},  {84, -1.0}, {88, -0.6},
                                        {96, -0.2}, {108, -0.1}, {118, -0.9}, {135, -4.2}, {155, -6.2},
                                        {180, -6.9}};
  return PiecewiseLinear(kLine, std::min(std::abs(azimuth_degrees), 180.0));
}

// How far above the hairline (cm) the shell reaches its full thickness: a
// gentle rise from the roots in front, a short one where the hair's ends
// hang over the ears and at the back.
double RootRise(double azimuth_degrees) {
  static constexpr double kRise[][2] = {{0, 3.0}, {40, 2.6}, {62, 1.8}, {80, 1.0}, {90, 0.45}, {130, 0.6}, {180, 0.8}};
  return PiecewiseLinear(kRise, std::min(std::abs(azimuth_degrees), 180.0));
}

// Full thickness (cm) by height and azimuth: most volume over the crown,
// less where the hair lies flat on the back of the head and the nape, and
// over the forehead, where it is swept back rather than piled up.
double FullThickness(double y, double azimuth_degrees) {
  static constexpr double kVolume[][2] = {{-7.0, 0.45}, {-3.0, 0.75}, {1.0, 0.95}, {6.0, 1.25}, {10.0, 1.4}};
  static constexpr double kFront[][2] = {{0, 0.55}, {45, 0.7}, {80, 1.0}};
  return PiecewiseLinear(kVolume, y) * PiecewiseLinear(kFront, std::min(std::abs(azimuth_degrees), 180.0));
}

double Azimuth(const glm::dvec3& p) {
  return std::atan2(p.x, p.z - SurfaceOrigin().z) * 180.0 / kPi;
}

// Height above the hairline (cm, negative below it).
double AboveHairline(const glm::dvec3& p) { return p.y - HairlineHeight(Azimuth(p)); }

// The hair drapes over the tops of the ears, which stand out about a
// centimetre from the skull: the shell bulges there by up to this much (cm).
double OverEar(const glm::dvec3& p) {
  constexpr double kBulge = 0.75;
  const glm::dvec3 q = (glm::dvec3(std::abs(p.x), p.y, p.z) - glm::dvec3(7.2, 0.6, -1.2)) / glm::dvec3(1.6, 1.8, 2.0);
  return kBulge * std::exp(-glm::dot(q, q));
}

double SmoothStep(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// How much hair covers a skin point: 1 above the hairline, 0 below it and
// where an ear stands out through the shell.
float HairCoverage(const cv::Vec3f& p) {
  const glm::dvec3 q(p[0], p[1], p[2]);
  // The painted line wanders a few millimetres about the sculpt's, as a
  // hairline does: broad bays and small tufts.
  const glm::vec3 at = glm::vec3(q);
  const double above = AboveHairline(q) + 0.3 * ValueNoise(at / 1.1f, 71) + 0.12 * ValueNoise(at / 0.35f, 72);
  if (above < -0.6) return 0.0f;
  double on_shell = 1.0;
  if (std::abs(q.x) > 5.5 && q.y > -5.0 && q.y < 3.0) {  // near an ear
    const double ear = BareHeadField(q, false) - BareHeadField(q, true);  // > 0: the ear stands out here
    if (ear > 0.0) on_shell = std::clamp(0.5 + (HairThickness(q) - ear) / 0.1, 0.0, 1.0);
  }
  return static_cast<float>(std::clamp(0.5 + above / 1.0, 0.0, 1.0) * on_shell);
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
  const double azimuth = Azimuth(p);
  const double above = p.y - HairlineHeight(azimuth);
  if (above <= 0.0) return 0.0;
  return (FullThickness(p.y, azimuth) + OverEar(p)) * SmoothStep(above / RootRise(azimuth));
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
      const float a = std::clamp(cover + (strand - 0.45f) * 1.6f * edge, 0.0f, 1.0f);
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
