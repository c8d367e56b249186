// Where a photo shows the face's skin, from its 68 landmarks and colours: the
// texture takes photo pixels only there (photo_texture.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "facerig/offline/error.h"
#include "facerig/offline/landmarks/dlib68.h"
#include "facerig/offline/photo/texture.h"
#include "geometry/smooth_step.h"
#include "photo/face_outline.h"
#include "geometry/bounding_box.h"

namespace facerig {
namespace {

std::vector<cv::Point> ToPoints(const std::vector<glm::vec2>& pixels, cv::Point origin) {
  std::vector<cv::Point> points;
  for (const glm::vec2& p : pixels) {
    points.emplace_back(static_cast<int>(std::lround(p.x)) - origin.x, static_cast<int>(std::lround(p.y)) - origin.y);
  }
  return points;
}

// The polygon filled with 1 in a float image, blurred, then mapped from
// [low, high] to [0, 1]: low and high near 0.5 centre the soft band on the
// edge, higher ones move it inside (and a sliver of a polygon drops out).
cv::Mat SoftPolygon(cv::Size size, const std::vector<cv::Point>& polygon, double sigma, float low, float high) {
  cv::Mat filled = cv::Mat::zeros(size, CV_32F);
  cv::fillPoly(filled, std::vector<std::vector<cv::Point>>{polygon}, cv::Scalar(1.0));
  cv::GaussianBlur(filled, filled, cv::Size(0, 0), sigma);
  filled.forEach<float>([&](float& value, const int*) { value = SmoothStep(low, high, value); });
  return filled;
}

// The cheeks' colour in CIELAB: the median over patches below each eye,
// between the jaw line and the nose.
cv::Vec3f CheekColour(const cv::Mat& lab, std::span<const glm::vec2> landmarks, cv::Point origin, float radius) {
  std::array<std::vector<float>, 3> channels;
  const std::array<glm::vec2, 2> centres{
      (landmarks[41] + landmarks[40] + landmarks[dlib68::kNostrilsFirst] + landmarks[2] +
       landmarks[dlib68::kOuterLipsFirst]) / 5.0f,
      (landmarks[46] + landmarks[47] + landmarks[dlib68::kNostrilsLast] + landmarks[14] +
       landmarks[dlib68::kLeftMouthCorner]) / 5.0f};
  const int r = std::max(1, static_cast<int>(radius));
  for (const glm::vec2& centre : centres) {
    const int cx = static_cast<int>(centre.x) - origin.x, cy = static_cast<int>(centre.y) - origin.y;
    for (int y = std::max(0, cy - r); y <= std::min(lab.rows - 1, cy + r); ++y) {
      for (int x = std::max(0, cx - r); x <= std::min(lab.cols - 1, cx + r); ++x) {
        const cv::Vec3f c = lab.at<cv::Vec3f>(y, x);
        for (int k = 0; k < 3; ++k) channels[static_cast<std::size_t>(k)].push_back(c[k]);
      }
    }
  }
  cv::Vec3f median(50.0f, 15.0f, 15.0f);
  for (int k = 0; k < 3; ++k) {
    std::vector<float>& values = channels[static_cast<std::size_t>(k)];
    if (values.empty()) return median;
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
    median[k] = values[values.size() / 2];
  }
  return median;
}

// Per pixel of the window: 1 near the cheeks' colour, fading to 0.
cv::Mat SkinLikeness(const RgbImage& photo, const cv::Rect& window, std::span<const glm::vec2> landmarks,
                     float face_size, const PhotoSkinMaskParams& params) {
  const cv::Mat rgb(photo.height, photo.width, CV_8UC3, const_cast<std::uint8_t*>(photo.pixels.data()));
  cv::Mat lab;
  rgb(window).convertTo(lab, CV_32FC3, 1.0 / 255.0);
  cv::cvtColor(lab, lab, cv::COLOR_RGB2Lab);
  const cv::Vec3f cheek = CheekColour(lab, landmarks, window.tl(), 0.04f * face_size);
  cv::Mat likeness(lab.size(), CV_32F);
  likeness.forEach<float>([&](float& value, const int* at) {
    const cv::Vec3f c = lab.at<cv::Vec3f>(at[0], at[1]);
    const float dl = params.lightness_weight * (c[0] - cheek[0]);
    const float da = params.chroma_weight * (c[1] - cheek[1]), db = params.chroma_weight * (c[2] - cheek[2]);
    value = 1.0f - SmoothStep(params.skin_distance_full, params.skin_distance_none, std::sqrt(dl * dl + da * da + db * db));
  });
  // Single pixels of hair near the skin's colour, or of skin in a shadow, blur away.
  cv::GaussianBlur(likeness, likeness, cv::Size(0, 0), std::max(1.0, 0.5 * params.softness * face_size));
  likeness.forEach<float>([](float& value, const int*) { value = SmoothStep(0.3f, 0.7f, value); });
  return likeness;
}

void CheckInputs(const RgbImage& photo, std::span<const glm::vec2> landmarks) {
  if (landmarks.size() != 68) throw InvalidInputError("photo skin mask: need dlib's 68 landmarks", "landmarks");
  for (const glm::vec2& p : landmarks) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) throw InvalidInputError("photo skin mask: a landmark is not finite", "landmarks");
  }
  if (photo.width <= 0 || photo.height <= 0 ||
      photo.pixels.size() != 3 * static_cast<std::size_t>(photo.width) * static_cast<std::size_t>(photo.height)) {
    throw InvalidInputError("photo skin mask: the photo's pixels do not match its size", "photo");
  }
}

}  // namespace

float PhotoSkinMask::At(int x, int y) const {
  if (weight.empty()) return 1.0f;
  x -= left, y -= top;
  if (x < 0 || y < 0 || x >= width || y >= height) return 0.0f;
  return weight[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)];
}

PhotoSkinMask BuildPhotoSkinMask(const RgbImage& photo, std::span<const glm::vec2> landmarks,
                                 const PhotoSkinMaskParams& params) {
  CheckInputs(photo, landmarks);
  const std::vector<glm::vec2> outline = FaceOutline(landmarks, params.forehead);
  const PixelBox box = BoxAround(std::span<const glm::vec2>(outline));
  const glm::vec2 low = box.low, high = box.high;
  const float face_size = std::max(high.x - low.x, high.y - low.y);
  const double sigma = std::max(1.0, static_cast<double>(params.softness * face_size));
  // The outline's box and a margin for the blur, clipped to the photo.
  const int margin = static_cast<int>(std::ceil(3.0 * sigma)) + 2;
  const cv::Rect window = cv::Rect(cv::Point(static_cast<int>(low.x) - margin, static_cast<int>(low.y) - margin),
                                   cv::Point(static_cast<int>(high.x) + margin + 1, static_cast<int>(high.y) + margin + 1)) &
                          cv::Rect(0, 0, photo.width, photo.height);
  // Landmarks wholly outside the photo: no pixel counts.
  if (window.area() == 0) return PhotoSkinMask{0, 0, 1, 1, {0.0f}};
  PhotoSkinMask mask{window.x, window.y, window.width, window.height, {}};
  const cv::Mat face = SoftPolygon(window.size(), ToPoints(outline, window.tl()), sigma, 0.5f, 0.98f);
  std::vector<glm::vec2> inner(landmarks.begin() + 17, landmarks.end());
  std::vector<cv::Point> inner_hull;
  cv::convexHull(ToPoints(inner, window.tl()), inner_hull);
  const cv::Mat trusted = SoftPolygon(window.size(), inner_hull, sigma, 0.25f, 0.6f);
  const std::vector<glm::vec2> inner_lips(landmarks.begin() + 60, landmarks.end());
  const cv::Mat mouth = SoftPolygon(window.size(), ToPoints(inner_lips, window.tl()), 0.4 * sigma, 0.3f, 0.6f);
  const cv::Mat skin = SkinLikeness(photo, window, landmarks, face_size, params);
  mask.weight.resize(static_cast<std::size_t>(window.area()));
  for (int y = 0; y < window.height; ++y) {
    for (int x = 0; x < window.width; ++x) {
      const float colour = std::max(trusted.at<float>(y, x), skin.at<float>(y, x));
      mask.weight[static_cast<std::size_t>(y) * static_cast<std::size_t>(window.width) + static_cast<std::size_t>(x)] =
          face.at<float>(y, x) * colour * (1.0f - mouth.at<float>(y, x));
    }
  }
  return mask;
}

RgbImage ShadeOutsideSkinMask(const RgbImage& photo, const PhotoSkinMask& mask) {
  RgbImage shaded = photo;
  const glm::vec3 tint(20.0f, 30.0f, 90.0f);
  for (int y = 0; y < photo.height; ++y) {
    for (int x = 0; x < photo.width; ++x) {
      const float out = 1.0f - mask.At(x, y);
      std::uint8_t* c = &shaded.pixels[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(photo.width) + static_cast<std::size_t>(x))];
      for (int k = 0; k < 3; ++k) {
        const float level = static_cast<float>(c[k]);
        c[k] = static_cast<std::uint8_t>(std::lround(level + out * (0.35f * level + tint[k] - level)));
      }
    }
  }
  return shaded;
}

}  // namespace facerig
