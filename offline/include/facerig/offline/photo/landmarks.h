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
#include "facerig/offline/photo/image.h"

namespace facerig {

struct PhotoLandmarkParams {
  // Faces smaller than this (the detection box's larger side) are refused:
  // the 68 points are unreliable below it, and dlib's detector window is 80 px.
  int min_face_pixels = 80;
};

struct PhotoLandmarks {
  std::vector<glm::vec2> pixels;  // dlib's 68 points, pixel centres (row 0 at the top)
  ImageFaceBox box;  // the face they were read from
  int faces_found = 0;
  std::vector<std::string> notes;  // e.g. "3 faces found; the largest was used"
};

// The largest face of the photo and its 68 landmarks.
// \throw InvalidInputError on an empty or inconsistent image.
// \throw LandmarkDetectionError when no face is found, or the face is smaller
//        than min_face_pixels (the message gives its size).
PhotoLandmarks DetectPhotoLandmarks(LandmarkDetector& detector, const RgbImage& photo,
                                    const PhotoLandmarkParams& params = {});

}  // namespace facerig
