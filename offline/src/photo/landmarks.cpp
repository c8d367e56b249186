// The largest face of a photograph and its 68 landmarks (dlib stays in landmarks.cpp).
#include <algorithm>
#include <cmath>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "facerig/offline/photo/landmarks.h"
#include "facerig/offline/error.h"
#include "facerig/offline/photo/face_cascade.h"
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

RgbImage Downscaled(const RgbImage& photo, double scale) {
  const cv::Mat source(photo.height, photo.width, CV_8UC3, const_cast<std::uint8_t*>(photo.pixels.data()));
  cv::Mat small;
  cv::resize(source, small, cv::Size(), scale, scale, cv::INTER_AREA);
  RgbImage out{small.cols, small.rows, {}};
  out.pixels.assign(small.data, small.data + small.total() * 3);
  return out;
}

// dlib's faces, found on a copy at most detect_max_side pixels a side (its
// time goes with the pixels; a portrait's face stays far above its 80 px
// window there), or on the photo itself when the copy shows none.
std::vector<ImageFaceBox> DlibFaceBoxes(const RgbImage& photo, const PhotoLandmarkParams& params) {
  const int longer = std::max(photo.width, photo.height);
  if (params.detect_max_side > 0 && longer > params.detect_max_side) {
    const double scale = static_cast<double>(params.detect_max_side) / static_cast<double>(longer);
    std::vector<ImageFaceBox> boxes = DetectFrontalFaceBoxes(Downscaled(photo, scale));
    if (!boxes.empty()) {
      for (ImageFaceBox& box : boxes) {
        box.left = static_cast<int>(std::lround(box.left / scale));
        box.top = static_cast<int>(std::lround(box.top / scale));
        box.right = static_cast<int>(std::lround(box.right / scale));
        box.bottom = static_cast<int>(std::lround(box.bottom / scale));
      }
      return boxes;
    }
  }
  return DetectFrontalFaceBoxes(photo);
}

// The second detector's faces, as dlib's boxes; none without a cascade file.
std::vector<ImageFaceBox> CascadeFaceBoxes(const RgbImage& photo, const PhotoLandmarkParams& params) {
  if (params.face_cascade.empty()) return {};
  FaceCascade cascade(params.face_cascade);
  const int smallest = static_cast<int>(std::floor(static_cast<float>(params.min_face_pixels) / kHaarToDlibBox.scale));
  std::vector<ImageFaceBox> boxes = cascade.DetectFaceBoxes(photo, smallest);
  for (ImageFaceBox& box : boxes) box = DlibBoxFromHaar(box);
  return boxes;
}

}  // namespace

PhotoLandmarks FindPhotoFace(const RgbImage& photo, const PhotoLandmarkParams& params) {
  CheckPhoto(photo);
  std::vector<ImageFaceBox> boxes = DlibFaceBoxes(photo, params);
  PhotoLandmarks result;
  if (boxes.empty()) {
    boxes = CascadeFaceBoxes(photo, params);
    result.detector = "haar";
  }
  if (boxes.empty()) {
    throw LandmarkDetectionError("photo: no face found (a frontal or near-frontal face of at least " +
                                     std::to_string(params.min_face_pixels) + " px is needed" +
                                     (params.face_cascade.empty() ? "; dlib's detector only: no Haar cascade to try "
                                                                    "(opencv-data, --face-cascade)" : "") + ")",
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
  result.box = *largest;
  result.faces_found = static_cast<int>(boxes.size());
  if (result.detector == "haar") {
    result.notes.push_back("dlib's face detector found no face; OpenCV's Haar cascade did (" +
                           params.face_cascade.string() + ")");
  }
  if (boxes.size() > 1) {
    result.notes.push_back(std::to_string(boxes.size()) + " faces found; the largest (" +
                           std::to_string(BoxSize(*largest)) + " px) was used");
  }
  return result;
}

void PlacePhotoLandmarks(LandmarkDetector& detector, const RgbImage& photo, PhotoLandmarks& face) {
  CheckPhoto(photo);
  face.pixels = detector.PredictLandmarks(photo, face.box);
  if (face.detector == "haar") {
    face.box = DlibBoxFromPoints(face.pixels);
    face.pixels = detector.PredictLandmarks(photo, face.box);
  }
}

PhotoLandmarks DetectPhotoLandmarks(LandmarkDetector& detector, const RgbImage& photo,
                                    const PhotoLandmarkParams& params) {
  PhotoLandmarks result = FindPhotoFace(photo, params);
  PlacePhotoLandmarks(detector, photo, result);
  return result;
}

}  // namespace facerig
