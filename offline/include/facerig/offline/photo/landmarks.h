// dlib's 68 landmarks found on a photograph (the face detector, then the
// shape predictor), with the detection box and a score.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/photo/face_cascade.h"
#include "facerig/offline/photo/image.h"

namespace facerig {

struct PhotoLandmarkParams {
  // Faces smaller than this (the detection box's larger side) are refused:
  // the 68 points are unreliable below it, and dlib's detector window is 80 px.
  int min_face_pixels = 80;
  // When positive, dlib's detector looks at a copy of the photo at most this
  // many pixels on its longer side (its time goes with the pixels), and at the
  // photo itself when the copy shows no face; the 68 points are always placed
  // on the photo itself. Off (0) by default: the copy's box differs (on the
  // astronaut at 1024 px, 640 px gave a 202 px box for 180 px), and the fitted
  // face with it (1.0 mm on average).
  int detect_max_side = 0;
  // OpenCV's Haar cascade (face_cascade.h), asked only when dlib's detector
  // finds no face; empty: no second detector.
  std::filesystem::path face_cascade = DefaultFaceCascadePath();
};

struct PhotoLandmarks {
  std::vector<glm::vec2> pixels;  // dlib's 68 points, pixel centres (row 0 at the top)
  ImageFaceBox box;  // the face they were read from
  int faces_found = 0;
  // The detector that found the face: "dlib", or "haar" (OpenCV's cascade,
  // the box moved to where dlib's would be) when dlib's found none.
  std::string detector = "dlib";
  std::vector<std::string> notes;  // e.g. "3 faces found; the largest was used"
};

// The largest face of the photo and its 68 landmarks: dlib's detector, else
// (no face found) the Haar cascade's most confirmed face, the 68 points placed
// by dlib's shape predictor in either case.
// \throw InvalidInputError on an empty or inconsistent image.
// \throw IoError when the cascade is needed and cannot be read.
// \throw LandmarkDetectionError when no face is found, or the face is smaller
//        than min_face_pixels (the message gives its size).
PhotoLandmarks DetectPhotoLandmarks(LandmarkDetector& detector, const RgbImage& photo,
                                    const PhotoLandmarkParams& params = {});

// The same in two steps: the face (box, faces_found, detector, notes; no
// points yet), which needs no shape predictor, then its 68 points (a Haar box
// is replaced by the box dlib's detector gives about the points placed from
// it, and the points placed again).
PhotoLandmarks FindPhotoFace(const RgbImage& photo, const PhotoLandmarkParams& params = {});
void PlacePhotoLandmarks(LandmarkDetector& detector, const RgbImage& photo, PhotoLandmarks& face);

}  // namespace facerig
