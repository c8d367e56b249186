// A picture of a photo fit, to look at: the detection, dlib's landmarks and
// the fitted model's landmarks on the photo.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/offline/photo/fit.h"
#include "facerig/offline/photo/landmarks.h"

namespace facerig {

// The photo with the detection box (yellow), dlib's 68 landmarks (green; jaw
// cyan) and the fitted model's projected landmarks (red), joined by lines.
RgbImage DrawPhotoFit(const RgbImage& photo, const PhotoLandmarks& landmarks, const PhotoFit& fit);
// DrawPhotoFit written as PNG. \throw std::runtime_error when writing fails.
void WritePhotoFitPng(const std::filesystem::path& path, const RgbImage& photo, const PhotoLandmarks& landmarks,
                      const PhotoFit& fit);

}  // namespace facerig
