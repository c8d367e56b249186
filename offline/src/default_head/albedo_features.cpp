// The painted features of the default head's skin texture (the hair is
// default_head_hair.cpp's): brows of hair-like strokes, lid creases and lash lines, and
// the lips with their vermilion border. Each is placed from the head's own
// geometry (feature points and margin chains) through the skin's UV map.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <opencv2/imgproc.hpp>

#include "default_head/albedo.h"
#include "default_head/angles.h"

namespace facerig::default_head {
namespace {

// A polyline through skin points, drawn anti-aliased into an 8-bit mask.
void DrawPolyline(const SkinCanvas& canvas, cv::Mat& mask, const std::vector<glm::dvec3>& points, int thickness) {
  std::vector<cv::Point> pixels;
  for (const glm::dvec3& p : points) pixels.push_back(canvas.FixedPixel(p));
  cv::polylines(mask, std::vector<std::vector<cv::Point>>{pixels}, false, cv::Scalar(255), thickness, cv::LINE_AA,
                SkinCanvas::kShift);
}

// An 8-bit mask as 0..1 floats, softened by `blur` pixels (0: not at all).
cv::Mat SoftMask(const cv::Mat& mask, double blur) {
  cv::Mat soft;
  mask.convertTo(soft, CV_32F, 1.0 / 255.0);
  if (blur > 0.0) cv::GaussianBlur(soft, soft, cv::Size(0, 0), blur);
  return soft;
}

// Multiplies the canvas by `factor` (B, G, R) where `mask` (0..1) is set.
void Darken(SkinCanvas& canvas, const cv::Mat& mask, const cv::Vec3f& factor) {
  for (int y = 0; y < canvas.size; ++y) {
    const float* m = mask.ptr<float>(y);
    auto* c = canvas.colour.ptr<cv::Vec3f>(y);
    for (int x = 0; x < canvas.size; ++x) {
      const float a = std::clamp(m[x], 0.0f, 1.0f);
      for (int k = 0; k < 3; ++k) c[x][k] *= 1.0f - a * (1.0f - factor[k]);
    }
  }
}

std::vector<glm::dvec3> Positions(const HeadGeometry& head, std::uint32_t first, const std::vector<std::uint32_t>& chain,
                                  std::uint32_t last) {
  std::vector<glm::dvec3> points = {head.positions[first]};
  for (std::uint32_t v : chain) points.push_back(head.positions[v]);
  points.push_back(head.positions[last]);
  return points;
}

}  // namespace

void PaintBrows(SkinCanvas& canvas) {
  const HeadGeometry& head = *canvas.head;
  cv::Mat mask(canvas.size, canvas.size, CV_8U, cv::Scalar::all(0));
  for (const char* side : {"_L", "_R"}) {
    const std::string s = side;
    const std::vector<glm::dvec3> curve = SmoothCurve(
        {head.positions[head.control.Find("brow_inner" + s)], head.positions[head.control.Find("brow_mid" + s)],
         head.positions[head.control.Find("brow_outer" + s)]},
        64);
    cv::RNG rng(s == "_L" ? 41 : 42);
    for (int i = 0; i < 420; ++i) {
      const double t = rng.uniform(0.0, 1.0);
      const auto k = static_cast<std::size_t>(std::lround(t * 62.0));
      const glm::dvec3 along = glm::normalize(curve[k + 1] - curve[k]);
      const glm::dvec3 up = glm::normalize(glm::dvec3(0.0, 1.0, 0.0) - along * along.y);
      const double thickness = 0.6 * (1.0 - t) + 0.2 * t;
      const glm::dvec3 root = curve[k] + up * (rng.uniform(-0.5, 0.5) * thickness - 0.2);
      // Hairs rise at the inner end and lie along the brow towards the tail.
      const double rise = t < 0.25 ? 70.0 - 200.0 * t : 20.0 - 40.0 * (t - 0.25);
      const double angle = Radians(rise + rng.uniform(-12.0, 12.0));
      const double length = rng.uniform(0.3, 0.55);
      const glm::dvec3 tip = root + length * (std::cos(angle) * along + std::sin(angle) * up);
      cv::line(mask, canvas.FixedPixel(root), canvas.FixedPixel(tip), cv::Scalar(rng.uniform(140, 256)), 1,
               cv::LINE_AA, SkinCanvas::kShift);
    }
  }
  BlendColour(canvas, SoftMask(mask, 4.0), Bgr(0.42f, 0.28f, 0.22f), 0.5f);
  BlendColour(canvas, SoftMask(mask, 0.0), Bgr(0.17f, 0.11f, 0.08f), 0.9f);
}

void PaintLids(SkinCanvas& canvas) {
  const HeadGeometry& head = *canvas.head;
  cv::Mat crease(canvas.size, canvas.size, CV_8U, cv::Scalar::all(0));
  cv::Mat lashes = crease.clone(), lower = crease.clone();
  for (int side = 0; side < 2; ++side) {
    const auto s = static_cast<std::size_t>(side);
    const glm::dvec3 eye = Anatomy::EyeCentre(side);
    const double radius = Anatomy::kEyeRadius + Anatomy::kLidOffset + 0.05;
    std::vector<glm::dvec3> arc;
    for (double az = -48.0; az <= 52.0; az += 4.0) {
      const double el = Radians(38.0 + 14.0 * std::cos(Radians(az) * 1.7));
      const double a = Radians(side == 0 ? az : -az);
      arc.push_back(eye + radius * glm::dvec3(std::sin(a) * std::cos(el), std::sin(el), std::cos(a) * std::cos(el)));
    }
    DrawPolyline(canvas, crease, arc, 3);
    const ControlMesh::Opening& opening = head.control.eyes[s];
    DrawPolyline(canvas, lashes, Positions(head, opening.corner_a, head.upper_lid[s], opening.corner_b), 4);
    DrawPolyline(canvas, lower, Positions(head, opening.corner_a, head.lower_lid[s], opening.corner_b), 2);
  }
  // Creases are the skin in shadow, a little darker and browner, never a colour of their own.
  Darken(canvas, SoftMask(crease, 3.0), cv::Vec3f(0.80f, 0.82f, 0.86f));
  Darken(canvas, SoftMask(lower, 1.2), cv::Vec3f(0.86f, 0.86f, 0.90f));
  BlendColour(canvas, SoftMask(lashes, 0.8), Bgr(0.08f, 0.06f, 0.05f), 0.95f);
}

namespace {

// The vermilion border of one lip: a smooth curve through the lip's outer
// control points from the right mouth corner to the left; the upper one
// with a Cupid's bow (raised either side of the philtrum).
std::vector<glm::dvec3> VermilionBorder(const HeadGeometry& head, const char* outer, bool upper) {
  const ControlMesh& c = head.control;
  const std::string o = outer;
  std::vector<glm::dvec3> border = SmoothCurve(
      {head.positions[c.mouth.corner_a], head.positions[c.Find(o + "_R")], head.positions[c.Find(o)],
       head.positions[c.Find(o + "_L")], head.positions[c.mouth.corner_b]},
      97);
  if (upper) {
    for (glm::dvec3& p : border) {
      p.y += 0.12 * std::exp(-std::pow((std::abs(p.x) - 0.5) / 0.3, 2.0)) - 0.06 * std::exp(-std::pow(p.x / 0.22, 2.0));
    }
  }
  return border;
}

// A closed polygon of skin points filled into an 8-bit mask.
cv::Mat FilledPolygon(const SkinCanvas& canvas, const std::vector<glm::dvec3>& polygon) {
  cv::Mat mask(canvas.size, canvas.size, CV_8U, cv::Scalar::all(0));
  std::vector<cv::Point> pixels;
  for (const glm::dvec3& p : polygon) pixels.push_back(canvas.FixedPixel(p));
  cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{pixels}, cv::Scalar(255), cv::LINE_AA, SkinCanvas::kShift);
  return mask;
}

// Faint vertical creases across a lip, from the margin towards the border.
void DrawLipCreases(const SkinCanvas& canvas, cv::Mat& mask, const std::vector<glm::dvec3>& margin,
                    const std::vector<glm::dvec3>& border) {
  const std::size_t count = 34;
  for (std::size_t i = 2; i + 2 < count; ++i) {
    const double f = static_cast<double>(i) / (count - 1);
    const glm::dvec3 m = margin[static_cast<std::size_t>(std::lround(f * static_cast<double>(margin.size() - 1)))];
    const glm::dvec3 b = border[static_cast<std::size_t>(std::lround(f * static_cast<double>(border.size() - 1)))];
    cv::line(mask, canvas.FixedPixel(m + 0.1 * (b - m)), canvas.FixedPixel(m + 0.7 * (b - m)), cv::Scalar(255), 1,
             cv::LINE_AA, SkinCanvas::kShift);
  }
}

}  // namespace

void PaintLips(SkinCanvas& canvas) {
  const HeadGeometry& head = *canvas.head;
  const ControlMesh::Opening& mouth = head.control.mouth;
  const std::vector<glm::dvec3> upper_margin = Positions(head, mouth.corner_a, head.upper_lip, mouth.corner_b);
  const std::vector<glm::dvec3> lower_margin = Positions(head, mouth.corner_a, head.lower_lip, mouth.corner_b);
  const std::vector<glm::dvec3> upper_border = VermilionBorder(head, "lip_upper_outer", true);
  const std::vector<glm::dvec3> lower_border = VermilionBorder(head, "lip_lower_outer", false);
  // Each lip: its border from right to left, back along its margin.
  std::vector<glm::dvec3> upper = upper_border, lower = lower_border, opening = upper_margin;
  upper.insert(upper.end(), upper_margin.rbegin(), upper_margin.rend());
  lower.insert(lower.end(), lower_margin.rbegin(), lower_margin.rend());
  opening.insert(opening.end(), lower_margin.rbegin() + 1, lower_margin.rend() - 1);
  BlendColour(canvas, SoftMask(FilledPolygon(canvas, upper), 0.7), Bgr(0.69f, 0.35f, 0.35f), 0.88f);
  BlendColour(canvas, SoftMask(FilledPolygon(canvas, lower), 0.7), Bgr(0.75f, 0.40f, 0.39f), 0.85f);
  BlendColour(canvas, SoftMask(FilledPolygon(canvas, opening), 0.7), Bgr(0.55f, 0.25f, 0.25f), 1.0f);
  cv::Mat creases(canvas.size, canvas.size, CV_8U, cv::Scalar::all(0));
  DrawLipCreases(canvas, creases, upper_margin, upper_border);
  DrawLipCreases(canvas, creases, lower_margin, lower_border);
  BlendColour(canvas, SoftMask(creases, 0.6), Bgr(0.45f, 0.22f, 0.22f), 0.18f);
}

}  // namespace facerig::default_head
