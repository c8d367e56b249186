// OpenCV's Haar cascade face detector (Debian opencv-data): the photo's second
// detector, asked only where dlib's HOG detector finds no face (it misses
// faces turned or lit from the side that the cascade still finds). Its boxes
// are moved and scaled to where dlib's detector puts its box on the same face,
// so dlib's shape predictor, trained on dlib's boxes, places the 68 points as
// it would from dlib's own box.
#pragma once

#include <filesystem>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/render/rasterizer.h"

namespace facerig {

// The cascade file: the one CMake found beside OpenCV at configure time,
// else the first `opencv4/haarcascades/` or `opencv/haarcascades/` copy under
// $XDG_DATA_DIRS (default /usr/local/share:/usr/share); empty when there is none.
std::filesystem::path DefaultFaceCascadePath();

// How a Haar box differs from dlib's on the same face, in units of the Haar
// box's width: dlib's centre = Haar's centre + (dx, dy) x width, dlib's side =
// scale x width. Measured on faces both detectors find (the "[.measure_cascade]"
// test: renders of random ICT-FaceKit identities and real photographs).
struct HaarToDlibBox {
  float dx = 0.0f;
  float dy = 0.0f;
  float scale = 1.0f;
};

// On 120 renders (6 identities, yaws -15 to 15, five lights) and dlib's example
// photographs: dx +0.001 (sd 0.025), dy +0.083 (sd 0.048), scale 0.909 (sd 0.082).
inline constexpr HaarToDlibBox kHaarToDlibBox{0.0f, 0.083f, 0.909f};

// The box dlib's detector would give for the face in Haar box `haar` (score kept).
ImageFaceBox DlibBoxFromHaar(const ImageFaceBox& haar, const HaarToDlibBox& correction = kHaarToDlibBox);

// dlib's box about its own 68 points, in units of the points' spread (their
// RMS distance from their mean): its centre = the points' mean + (dx, dy) x
// spread, its side = scale x spread. A Haar box (a different size on some
// faces: on a face lit from one side it may frame the lit part) gives
// points, the points give the box dlib would have given, which gives the
// points again. Measured as kHaarToDlibBox.
struct PointsToDlibBox {
  float dx = 0.0f;
  float dy = 0.0f;
  float scale = 1.0f;
};

// dx -0.002 (sd 0.084), dy -0.114 (sd 0.137), scale 2.874 (sd 0.196).
inline constexpr PointsToDlibBox kPointsToDlibBox{0.0f, -0.114f, 2.874f};

// The box dlib's detector would give for a face with these 68 points.
ImageFaceBox DlibBoxFromPoints(std::span<const glm::vec2> points, const PointsToDlibBox& correction = kPointsToDlibBox);

class FaceCascade {
 public:
  // \throw IoError (kOpenFailed) when `file` cannot be read, (kParse) when it
  //        is not a cascade OpenCV can load.
  explicit FaceCascade(const std::filesystem::path& file);
  ~FaceCascade();
  FaceCascade(FaceCascade&&) noexcept;
  FaceCascade& operator=(FaceCascade&&) noexcept;

  // Every face of at least `min_face_pixels` (the Haar box's side), as Haar
  // boxes, the most confirmed first (score: the detections merged into it).
  std::vector<ImageFaceBox> DetectFaceBoxes(const RgbImage& image, int min_face_pixels);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace facerig
