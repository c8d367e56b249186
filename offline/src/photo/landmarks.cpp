// The largest face of a photograph and its 68 landmarks (dlib stays in landmarks.cpp).
#include <algorithm>
#include <string>

#include "facerig/offline/photo/landmarks.h"
#include "facerig/offline/error.h"
#include "facerig/offline/photo/fit.h"

namespace facerig {

namespace {

void CheckPhoto(const RgbImage& photo) {
  if (photo.width <= 0 || photo.height <= 0 ||
      photo.pixels.size() != static_cast<std::size_t>(photo.width) * static_cast<std::size_t>(photo.height) * 3) {
    throw InvalidInputError("photo landmarks: the image is empty or its pixel count does not match its size",
                            "photo");
  }
}

int BoxSize(const ImageFaceBox& box) { return std::max(box.width(), box.height()); }

}  // namespace

PhotoLandmarks DetectPhotoLandmarks(LandmarkDetector& detector, const RgbImage& photo,
                                    const PhotoLandmarkParams& params) {
  CheckPhoto(photo);
  const std::vector<ImageFaceBox> boxes = detector.DetectFaceBoxes(photo);
  if (boxes.empty()) {
    throw LandmarkDetectionError("photo: no face found (a frontal or near-frontal face of at least " +
                                     std::to_string(params.min_face_pixels) + " px is needed)",
                                 "photo");
  }
  const auto largest = std::max_element(boxes.begin(), boxes.end(), [](const ImageFaceBox& a, const ImageFaceBox& b) {
    return BoxSize(a) < BoxSize(b);
  });
  if (BoxSize(*largest) < params.min_face_pixels) {
    throw LandmarkDetectionError("photo: the face is " + std::to_string(BoxSize(*largest)) +
                                     " px, smaller than the " + std::to_string(params.min_face_pixels) +
                                     " px needed for reliable landmarks",
                                 "photo", std::to_string(BoxSize(*largest)));
  }
  PhotoLandmarks result;
  result.box = *largest;
  result.faces_found = static_cast<int>(boxes.size());
  result.pixels = detector.PredictLandmarks(photo, result.box);
  if (boxes.size() > 1) {
    result.notes.push_back(std::to_string(boxes.size()) + " faces found; the largest (" +
                           std::to_string(BoxSize(*largest)) + " px) was used");
  }
  return result;
}

}  // namespace facerig
