// The photo fit's debug picture: detection box, dlib's landmarks and the
// fitted model's projected landmarks over the photo.
#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "facerig/offline/photo/debug.h"
#include "facerig/offline/photo/landmarks.h"
#include "facerig/offline/photo/fit.h"

namespace facerig {

namespace {

cv::Point ToCv(glm::vec2 pixel) {
  // Pixel centres are at +0.5.
  return {static_cast<int>(std::lround(pixel.x - 0.5f)), static_cast<int>(std::lround(pixel.y - 0.5f))};
}

}  // namespace

RgbImage DrawPhotoFit(const RgbImage& photo, const PhotoLandmarks& landmarks, const PhotoFit& fit) {
  RgbImage out = photo;
  cv::Mat canvas(out.height, out.width, CV_8UC3, out.pixels.data());
  const int thickness = std::max(1, std::max(out.width, out.height) / 400);
  const int radius = std::max(2, 2 * thickness);
  const ImageFaceBox& box = landmarks.box;
  cv::rectangle(canvas, cv::Point(box.left, box.top), cv::Point(box.right - 1, box.bottom - 1),
                cv::Scalar(255, 220, 0), thickness);
  const std::size_t count = std::min(landmarks.pixels.size(), fit.model_pixels.size());
  for (std::size_t k = 0; k < count; ++k) {
    cv::line(canvas, ToCv(landmarks.pixels[k]), ToCv(fit.model_pixels[k]), cv::Scalar(255, 255, 255), 1);
  }
  for (std::size_t k = 0; k < landmarks.pixels.size(); ++k) {
    const cv::Scalar colour = k < 17 ? cv::Scalar(0, 220, 255) : cv::Scalar(0, 230, 0);  // RGB order
    cv::circle(canvas, ToCv(landmarks.pixels[k]), radius, colour, cv::FILLED);
  }
  for (const glm::vec2 p : fit.model_pixels) cv::circle(canvas, ToCv(p), radius, cv::Scalar(255, 40, 40), thickness);
  return out;
}

void WritePhotoFitPng(const std::filesystem::path& path, const RgbImage& photo, const PhotoLandmarks& landmarks,
                      const PhotoFit& fit) {
  WritePng(path, DrawPhotoFit(photo, landmarks, fit));
}

}  // namespace facerig
