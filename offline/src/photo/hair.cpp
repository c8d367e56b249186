// Where a photo shows the head's hair, and its colour: the head (face and
// hair) cut from the background by GrabCut, seeded from the 68 landmarks.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "facerig/offline/error.h"
#include "facerig/offline/landmarks/dlib68.h"
#include "facerig/offline/photo/texture.h"
#include "facerig/offline/geometry/stats.h"
#include "geometry/smooth_step.h"
#include "photo/face_outline.h"
#include "geometry/bounding_box.h"

namespace facerig {
namespace {

// The landmarks' box: x from the jaw's sides, y from the brows to the chin.
struct FaceBox {
  glm::vec2 low{0.0f}, high{0.0f};
  float width() const { return high.x - low.x; }
  float height() const { return high.y - low.y; }
};

FaceBox BoxOf(std::span<const glm::vec2> landmarks) {
  const PixelBox box = BoxAround(landmarks);
  return {box.low, box.high};
}

// The part of the photo a head round this face can cover: hair reaches about
// a face's height above the brows and half a face's width beside the jaw.
cv::Rect HeadWindow(const FaceBox& face, const RgbImage& photo) {
  const cv::Point from(static_cast<int>(face.low.x - 0.7f * face.width()), static_cast<int>(face.low.y - 1.1f * face.height()));
  const cv::Point to(static_cast<int>(face.high.x + 0.7f * face.width()), static_cast<int>(face.high.y + 0.2f * face.height()));
  return cv::Rect(from, to) & cv::Rect(0, 0, photo.width, photo.height);
}

// GrabCut's seeds on the scaled window: the face inside the jaw line sure
// head, the band above the brows probably head, the window's edges that are
// not the photo's edges (hair may run off the photo) sure background.
cv::Mat Seeds(cv::Size size, const cv::Rect& window, const RgbImage& photo, std::span<const glm::vec2> landmarks,
              const FaceBox& face, double scale) {
  cv::Mat seeds(size, CV_8U, cv::Scalar(cv::GC_PR_BGD));
  const auto at = [&](glm::vec2 p) {
    return cv::Point(static_cast<int>((p.x - static_cast<float>(window.x)) * scale),
                     static_cast<int>((p.y - static_cast<float>(window.y)) * scale));
  };
  const glm::vec2 top_left(face.low.x - 0.1f * face.width(), face.low.y - 0.8f * face.height());
  const glm::vec2 bottom_right(face.high.x + 0.1f * face.width(), face.low.y);
  cv::rectangle(seeds, at(top_left), at(bottom_right), cv::Scalar(cv::GC_PR_FGD), cv::FILLED);
  std::vector<cv::Point> outline;
  for (const glm::vec2 p : FaceOutline(landmarks, 0.2f)) outline.push_back(at(p));
  cv::fillPoly(seeds, std::vector<std::vector<cv::Point>>{outline}, cv::Scalar(cv::GC_FGD));
  const int band = std::max(2, size.width / 40);
  const auto background = [&](cv::Rect r) { cv::rectangle(seeds, r & cv::Rect(cv::Point(0, 0), size), cv::Scalar(cv::GC_BGD), cv::FILLED); };
  if (window.x > 0) background({0, 0, band, size.height});
  if (window.x + window.width < photo.width) background({size.width - band, 0, band, size.height});
  if (window.y > 0) background({0, 0, size.width, band});
  background({0, size.height - band, size.width, band});
  return seeds;
}

// The head's foreground on the scaled window (1 head, 0 background).
cv::Mat SegmentHead(const cv::Mat& image, cv::Mat seeds, int iterations) {
  cv::Mat background_model, foreground_model;
  cv::grabCut(image, seeds, cv::Rect(), background_model, foreground_model, iterations, cv::GC_INIT_WITH_MASK);
  cv::Mat head(seeds.size(), CV_32F);
  head.forEach<float>([&](float& value, const int* at) {
    const std::uint8_t label = seeds.at<std::uint8_t>(at[0], at[1]);
    value = label == cv::GC_FGD || label == cv::GC_PR_FGD ? 1.0f : 0.0f;
  });
  // One scaled pixel in from the edge: its colour is part background.
  cv::erode(head, head, cv::Mat());
  return head;
}

// Median of the pixels surely hair: head, not skin, above the brows.
bool HairColour(const RgbImage& photo, const PhotoSkinMask& head, const PhotoSkinMask& skin, float brows_y,
                glm::vec3& colour) {
  std::array<std::vector<float>, 3> channels;
  const int bottom = std::min(head.top + head.height, static_cast<int>(brows_y));
  for (int y = head.top; y < bottom; ++y) {
    for (int x = head.left; x < head.left + head.width; ++x) {
      if (head.At(x, y) < 0.95f || skin.At(x, y) > 0.05f) continue;
      const std::uint8_t* c = &photo.pixels[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(photo.width) + static_cast<std::size_t>(x))];
      for (int k = 0; k < 3; ++k) channels[static_cast<std::size_t>(k)].push_back(static_cast<float>(c[k]) / 255.0f);
    }
  }
  if (channels[0].size() < 64) return false;
  for (int k = 0; k < 3; ++k) colour[k] = Median(std::move(channels[static_cast<std::size_t>(k)]));
  return true;
}

}  // namespace

PhotoHair FindPhotoHair(const RgbImage& photo, std::span<const glm::vec2> landmarks, const PhotoSkinMask& skin,
                        const PhotoHairParams& params) {
  if (landmarks.size() != 68) throw InvalidInputError("photo hair: need dlib's 68 landmarks", "landmarks");
  if (photo.width <= 0 || photo.height <= 0 ||
      photo.pixels.size() != 3 * static_cast<std::size_t>(photo.width) * static_cast<std::size_t>(photo.height)) {
    throw InvalidInputError("photo hair: the photo's pixels do not match its size", "photo");
  }
  PhotoHair hair;
  const FaceBox face = BoxOf(landmarks);
  const cv::Rect window = HeadWindow(face, photo);
  if (window.width < 8 || window.height < 8 || !(face.width() > 0.0f && face.height() > 0.0f)) return hair;
  const double scale = std::min(1.0, static_cast<double>(params.work_size) / std::max(window.width, window.height));
  const cv::Mat rgb(photo.height, photo.width, CV_8UC3, const_cast<std::uint8_t*>(photo.pixels.data()));
  cv::Mat small;
  cv::resize(rgb(window), small, cv::Size(0, 0), scale, scale, cv::INTER_AREA);
  cv::Mat head;
  try {
    head = SegmentHead(small, Seeds(small.size(), window, photo, landmarks, face, scale), params.iterations);
  } catch (const cv::Exception&) {
    return hair;  // seeds of one kind only: nothing to tell apart
  }
  cv::resize(head, head, window.size(), 0.0, 0.0, cv::INTER_LINEAR);
  hair.head = PhotoSkinMask{window.x, window.y, window.width, window.height, {}};
  hair.head.weight.resize(static_cast<std::size_t>(window.area()));
  for (int y = 0; y < window.height; ++y) {
    for (int x = 0; x < window.width; ++x) {
      hair.head.weight[static_cast<std::size_t>(y) * static_cast<std::size_t>(window.width) + static_cast<std::size_t>(x)] =
          SmoothStep(0.3f, 0.7f, head.at<float>(y, x));
    }
  }
  const float brows_y = std::min(landmarks[dlib68::kRightBrowPeak].y, landmarks[dlib68::kLeftBrowPeak].y);
  hair.found = HairColour(photo, hair.head, skin, brows_y, hair.colour);
  return hair;
}

}  // namespace facerig
