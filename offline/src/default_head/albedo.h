// The default head's painted skin texture while it is painted (OpenCV),
// shared by default_head_albedo*.cpp. Colours are sRGB in [0, 1], stored
// B, G, R as OpenCV keeps them.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <opencv2/core.hpp>

#include "default_head/internal.h"

namespace facerig::default_head {

struct SkinCanvas {
  const HeadGeometry* head = nullptr;
  int size = 0;
  cv::Mat colour;    // CV_32FC3
  cv::Mat position;  // CV_32FC3: the skin point (x, y, z) under the texel
  cv::Mat jaw;       // CV_32F: the jaw weight there
  cv::Mat covered;   // CV_8U: 255 where a skin triangle covers the texel

  // Where a point on (or near) the skin lands in the texture, in pixels.
  cv::Point2f Pixel(const glm::dvec3& p) const;
  // OpenCV's fixed-point polygon coordinates (kShift fraction bits).
  static constexpr int kShift = 4;
  cv::Point FixedPixel(const glm::dvec3& p) const;
};

// Colour as OpenCV stores it, from sRGB (r, g, b).
inline cv::Vec3f Bgr(float r, float g, float b) { return {b, g, r}; }

// Blends `colour` over the canvas by `mask` (CV_32F, 0..1) times `opacity`.
void BlendColour(SkinCanvas& canvas, const cv::Mat& mask, const cv::Vec3f& colour, float opacity);

// The painted features, each from the head's geometry.
void PaintHair(SkinCanvas& canvas);
void PaintBrows(SkinCanvas& canvas);
void PaintLids(SkinCanvas& canvas);
void PaintLips(SkinCanvas& canvas);

// 8-bit PNG of a CV_32FC3 image (B, G, R in [0, 1]).
EncodedImage EncodeFloatBgrPng(const cv::Mat& bgr_float, const char* name);

// A smooth curve (Catmull-Rom, ends repeated) through `points`, `samples` long.
std::vector<glm::dvec3> SmoothCurve(const std::vector<glm::dvec3>& points, int samples);

}  // namespace facerig::default_head
