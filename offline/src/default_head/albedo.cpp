// The default head's skin texture, painted in code: the skin's triangles are
// baked into the texture (each texel knows its skin point), a skin tone with
// low-frequency variation is laid down from those points, the texels no
// triangle covers are filled from their neighbours (so filtering never
// brings in black), then hair, brows, lids and lips are painted from the
// geometry's UVs. Deterministic: fixed seeds, no threads.
#include "default_head/albedo.h"
#include "geometry/value_noise.h"
#include "render/uv_raster.h"
#include "facerig/offline/default_head/default_head.h"
#include "facerig/offline/render/png_encode.h"
#include "facerig/offline/error.h"
#include "facerig/offline/io/image_codec.h"

#include <algorithm>
#include <cmath>
#include <span>

#include <glm/geometric.hpp>
#include <opencv2/imgproc.hpp>

namespace facerig::default_head {

cv::Point2f SkinCanvas::Pixel(const glm::dvec3& p) const {
  const glm::dvec2 uv = SkinUv(p);
  return {static_cast<float>(uv.x * size - 0.5), static_cast<float>(uv.y * size - 0.5)};
}

cv::Point SkinCanvas::FixedPixel(const glm::dvec3& p) const {
  const cv::Point2f q = Pixel(p);
  return {static_cast<int>(std::lround(q.x * (1 << kShift))), static_cast<int>(std::lround(q.y * (1 << kShift)))};
}

void BlendColour(SkinCanvas& canvas, const cv::Mat& mask, const cv::Vec3f& colour, float opacity) {
  for (int y = 0; y < canvas.size; ++y) {
    const float* m = mask.ptr<float>(y);
    auto* c = canvas.colour.ptr<cv::Vec3f>(y);
    for (int x = 0; x < canvas.size; ++x) {
      const float a = std::clamp(m[x] * opacity, 0.0f, 1.0f);
      c[x] = c[x] * (1.0f - a) + colour * a;
    }
  }
}

std::vector<glm::dvec3> SmoothCurve(const std::vector<glm::dvec3>& points, int samples) {
  std::vector<glm::dvec3> curve;
  const auto segments = static_cast<int>(points.size()) - 1;
  auto at = [&](int i) { return points[static_cast<std::size_t>(std::clamp(i, 0, segments))]; };
  for (int s = 0; s < samples; ++s) {
    const double t = static_cast<double>(s) / (samples - 1) * segments;
    const int i = std::min(static_cast<int>(t), segments - 1);
    const double u = t - i;
    const glm::dvec3 p0 = at(i - 1), p1 = at(i), p2 = at(i + 1), p3 = at(i + 2);
    curve.push_back(0.5 * ((2.0 * p1) + (p2 - p0) * u + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * u * u +
                           (3.0 * p1 - p0 - 3.0 * p2 + p3) * u * u * u));
  }
  return curve;
}

namespace {

// Each texel under a skin triangle gets the triangle's interpolated point and
// jaw weight (as the renderer interpolates UVs: linearly in the triangle).
void Bake(SkinCanvas& canvas, const std::vector<glm::vec2>& uvs) {
  const HeadGeometry& head = *canvas.head;
  const std::uint32_t skin_triangles = head.parts.front().triangle_count;
  for (std::uint32_t t = 0; t < skin_triangles; ++t) {
    const Triangle& tri = head.triangles[t];
    glm::dvec2 p[3];
    for (int k = 0; k < 3; ++k) p[k] = glm::dvec2(uvs[tri[k]]) * static_cast<double>(canvas.size) - 0.5;
    ForEachTexelIn(p, canvas.size, [&](int x, int y, double w0, double w1, double w2) {
      const glm::dvec3 point = w0 * head.positions[tri[0]] + w1 * head.positions[tri[1]] + w2 * head.positions[tri[2]];
      canvas.position.at<cv::Vec3f>(y, x) = cv::Vec3f(glm::vec3(point).x, glm::vec3(point).y, glm::vec3(point).z);
      canvas.jaw.at<float>(y, x) = static_cast<float>(w0 * head.jaw_weight[tri[0]] + w1 * head.jaw_weight[tri[1]] +
                                                      w2 * head.jaw_weight[tri[2]]);
      canvas.covered.at<std::uint8_t>(y, x) = 255;
    });
  }
}

// A soft tint about a point of the head (mirrored to both sides when sided).
struct Tint {
  glm::vec3 centre;
  float radius;  // cm: the Gaussian's sigma
  cv::Vec3f colour;
  float amount;
  bool sided;
};

// Skin tone: a base, tints where the face is redder (cheeks, nose, ears) or
// darker and greyer (the jaw's beard shadow, the neck), noise at two scales.
cv::Vec3f SkinTone(const glm::vec3& p, float jaw, float coarse_noise) {
  static const Tint kTints[] = {
      {{4.0f, -2.6f, 6.6f}, 1.5f, Bgr(0.86f, 0.50f, 0.47f), 0.45f, true},   // cheeks
      {{0.0f, -3.2f, 10.0f}, 1.1f, Bgr(0.86f, 0.52f, 0.48f), 0.45f, false},  // nose tip
      {{1.0f, -3.6f, 8.9f}, 0.5f, Bgr(0.84f, 0.50f, 0.46f), 0.35f, true},   // nose wings
      {{7.5f, -1.3f, -1.2f}, 1.9f, Bgr(0.86f, 0.50f, 0.47f), 0.45f, true},  // ears
      {{0.45f, -4.2f, 9.05f}, 0.22f, Bgr(0.36f, 0.20f, 0.18f), 0.85f, true},  // nostrils
      {{0.0f, -4.95f, 8.8f}, 0.7f, Bgr(0.70f, 0.58f, 0.54f), 0.25f, false},  // shadow above the lip
      {{2.7f, -6.35f, 7.3f}, 0.3f, Bgr(0.55f, 0.33f, 0.30f), 0.45f, true},  // mouth corners
      {{3.0f, -0.9f, 7.0f}, 0.6f, Bgr(0.72f, 0.52f, 0.52f), 0.3f, true},  // under the eyes
      {{0.0f, 5.0f, 7.2f}, 2.5f, Bgr(0.89f, 0.72f, 0.60f), 0.3f, false},  // forehead, yellower
  };
  cv::Vec3f colour = Bgr(0.88f, 0.68f, 0.57f);
  for (const Tint& tint : kTints) {
    glm::vec3 q = p;
    if (tint.sided) q.x = std::abs(q.x);
    const float d2 = glm::dot(q - tint.centre, q - tint.centre);
    const float a = tint.amount * std::exp(-0.5f * d2 / (tint.radius * tint.radius));
    colour = colour * (1.0f - a) + tint.colour * a;
  }
  const float beard = 0.28f * jaw * std::clamp((-6.6f - p.y) / 1.0f, 0.0f, 1.0f);
  colour = colour * (1.0f - beard) + Bgr(0.70f, 0.60f, 0.56f) * beard;
  const float neck = 0.25f * std::clamp((-11.5f - p.y) / 3.0f, 0.0f, 1.0f);
  colour = colour * (1.0f - neck) + Bgr(0.78f, 0.60f, 0.51f) * neck;
  return colour * (1.0f + coarse_noise);
}

// Value noise on the surface, cells of `cell` cm.
float SurfaceNoise(const cv::Vec3f& p, float cell, std::uint32_t seed) {
  return ValueNoise(glm::vec3(p[0], p[1], p[2]) / cell, seed);
}

void PaintSkinTone(SkinCanvas& canvas) {
  for (int y = 0; y < canvas.size; ++y) {
    for (int x = 0; x < canvas.size; ++x) {
      if (!canvas.covered.at<std::uint8_t>(y, x)) continue;
      const cv::Vec3f p = canvas.position.at<cv::Vec3f>(y, x);
      const float blotches = 0.035f * SurfaceNoise(p, 3.0f, 11) + 0.02f * SurfaceNoise(p, 0.9f, 12);
      canvas.colour.at<cv::Vec3f>(y, x) = SkinTone({p[0], p[1], p[2]}, canvas.jaw.at<float>(y, x), blotches);
    }
  }
}

// Push-pull: texels no triangle covers take the average of the covered ones
// around them, from the finest level of an image pyramid that has any.
void FillUncovered(SkinCanvas& canvas) {
  cv::Mat weight;
  canvas.covered.convertTo(weight, CV_32F, 1.0 / 255.0);
  cv::Mat weighted;
  cv::merge(std::vector<cv::Mat>{weight, weight, weight}, weighted);
  std::vector<cv::Mat> sums = {canvas.colour.mul(weighted)};
  std::vector<cv::Mat> weights = {weight};
  while (sums.back().cols > 4) {
    cv::Mat s, w;
    cv::resize(sums.back(), s, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    cv::resize(weights.back(), w, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    sums.push_back(s);
    weights.push_back(w);
  }
  cv::Mat filled;  // the normalised colour at the current level
  for (std::size_t level = sums.size(); level-- > 0;) {
    cv::Mat up;
    if (!filled.empty()) cv::resize(filled, up, sums[level].size(), 0.0, 0.0, cv::INTER_LINEAR);
    filled = cv::Mat(sums[level].size(), CV_32FC3, cv::Scalar::all(0.0));
    for (int y = 0; y < filled.rows; ++y) {
      for (int x = 0; x < filled.cols; ++x) {
        const float w = weights[level].at<float>(y, x);
        filled.at<cv::Vec3f>(y, x) = w > 1e-4f ? sums[level].at<cv::Vec3f>(y, x) / w
                                      : (up.empty() ? cv::Vec3f() : up.at<cv::Vec3f>(y, x));
      }
    }
  }
  filled.copyTo(canvas.colour, canvas.covered == 0);
}

// Fine, pore-scale variation, so the skin does not look airbrushed (on the
// skin; texels no triangle covers keep their filled colour).
void AddFineNoise(SkinCanvas& canvas) {
  for (int y = 0; y < canvas.size; ++y) {
    for (int x = 0; x < canvas.size; ++x) {
      if (!canvas.covered.at<std::uint8_t>(y, x)) continue;
      const cv::Vec3f p = canvas.position.at<cv::Vec3f>(y, x);
      canvas.colour.at<cv::Vec3f>(y, x) *= 1.0f + 0.025f * SurfaceNoise(p, 0.07f, 13) + 0.015f * SurfaceNoise(p, 0.25f, 14);
    }
  }
}

}  // namespace

EncodedImage EncodeFloatBgrPng(const cv::Mat& bgr_float, const char* name) {
  cv::Mat bytes, rgb;
  bgr_float.convertTo(bytes, CV_8UC3, 255.0);
  cv::cvtColor(bytes, rgb, cv::COLOR_BGR2RGB);
  return EncodePng(std::span<const std::uint8_t>(rgb.data, rgb.total() * 3), rgb.cols, rgb.rows, 3, name, 6);
}

EncodedImage PaintSkinAlbedo(const HeadGeometry& head, const std::vector<glm::vec2>& uvs) {
  SkinCanvas canvas;
  canvas.head = &head;
  canvas.size = kSkinTextureSize;
  const cv::Size size(canvas.size, canvas.size);
  canvas.colour = cv::Mat(size, CV_32FC3, cv::Scalar::all(0.0));
  canvas.position = cv::Mat(size, CV_32FC3, cv::Scalar::all(0.0));
  canvas.jaw = cv::Mat(size, CV_32F, cv::Scalar::all(0.0));
  canvas.covered = cv::Mat(size, CV_8U, cv::Scalar::all(0));
  Bake(canvas, uvs);
  PaintSkinTone(canvas);
  PaintHair(canvas);
  FillUncovered(canvas);
  PaintLids(canvas);
  PaintBrows(canvas);
  PaintLips(canvas);
  AddFineNoise(canvas);
  return EncodeFloatBgrPng(canvas.colour, "default_head_skin.png");
}

}  // namespace facerig::default_head

namespace facerig {

RgbImage DecodeImage(const EncodedImage& image) {
  cv::Mat bgr;
  try {
    bgr = DecodeImageBytes(image.bytes, DecodedChannels::kBgr);
  } catch (const InvalidInputError& error) {
    throw std::runtime_error("DecodeImage: '" + image.name + "' does not decode: " + error.what());
  }
  RgbImage rgb;
  rgb.width = bgr.cols;
  rgb.height = bgr.rows;
  rgb.pixels.reserve(static_cast<std::size_t>(bgr.cols) * static_cast<std::size_t>(bgr.rows) * 3);
  for (int y = 0; y < bgr.rows; ++y) {
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3b c = bgr.at<cv::Vec3b>(y, x);
      rgb.pixels.insert(rgb.pixels.end(), {c[2], c[1], c[0]});
    }
  }
  return rgb;
}

}  // namespace facerig
