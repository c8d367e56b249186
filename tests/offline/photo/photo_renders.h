// Photos of random ICT-FaceKit faces made by the project's rasterizer, shared
// by the photo tests (the fit's accuracy table, the face detectors): the
// template's face model, one dlib detector per process, and render styles
// (flat skin and light from above; side light; blotchy skin; noise).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/photo/fit.h"
#include "facerig/offline/render/rasterizer.h"
#include "facerig/offline/rigging/face_template.h"

namespace facerig::test {

inline constexpr float kPi = 3.14159265f;

struct IctPhotoSetup {
  FaceTemplateInfo info;
  PhotoFaceModel model;
};

// One detector for the process: loading dlib's predictor takes a good part of a second.
LandmarkDetector& Detector();
// ICT-FaceKit's photo model (../shared/data), built once.
const IctPhotoSetup& Setup();

std::vector<glm::vec3> FaceWithWeights(const PhotoFaceModel& model, const std::vector<double>& weights);

// Half the height the photo frames at the nose tip's depth (cm).
inline constexpr float kHalfFrame = 16.0f;

// The photo's camera looking at the nose tip: orthographic (distance 0) or a
// perspective camera `distance_cm` away, framing the same +-kHalfFrame at the nose tip.
RasterView PhotoView(glm::vec3 nose, float yaw_degrees, int size, float distance_cm);

// How a test photo is lit and painted: the default is one light 30 degrees
// above the view axis on a flat skin colour; `blotchy` paints the skin with
// smooth +-10 % blotches and darker brows and lips.
struct RenderStyle {
  glm::vec3 light{0.0f, 0.5f, 0.8660254f};
  float ambient = 0.25f;
  bool blotchy = false;
  // How far the fitted camera's yaw may be off (degrees).
  float yaw_tolerance = 4.0f;
  // Gaussian pixel noise (standard deviation, fractions of full scale).
  float noise = 0.0f;
  // A perspective photo from this far (cm; 0: orthographic).
  float distance_cm = 0.0f;
};

// 40 degrees off the view axis, from the upper left, and little ambient light.
RenderStyle SideLight();
RenderStyle Blotchy();
// All at once: side light, blotchy skin and pixel noise (a camera's at ISO 800 or so).
RenderStyle Hard();

// The head rendered with Lambert light; the eye films (transparent in ICT) left out.
RgbImage RenderFace(const FaceTemplateInfo& info, const std::vector<glm::vec3>& positions, float yaw_degrees,
                    int size, const RenderStyle& style = {});

// The landmark vertices' exact projections into a render of `rendered`: what
// a perfect detector would give (the jaw at its fixed vertices).
std::vector<glm::vec2> ExactLandmarks(const FaceTemplateInfo& info, const std::vector<glm::vec3>& rendered,
                                      float yaw_degrees, int size, float distance_cm);

}  // namespace facerig::test
