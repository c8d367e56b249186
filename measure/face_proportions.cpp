#include "measure/face_proportions.h"

#include <cmath>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

namespace facerig::test {
namespace {

// The landmark seen front-on.
glm::dvec2 Front(const FaceLandmarks& landmarks, std::size_t k) {
  return {landmarks.points[k].x, landmarks.points[k].y};
}

double Between(const FaceLandmarks& landmarks, std::size_t a, std::size_t b) {
  return glm::length(Front(landmarks, a) - Front(landmarks, b));
}

glm::dvec2 EyeCentre(const FaceLandmarks& landmarks, std::size_t first) {
  glm::dvec2 sum(0.0);
  for (std::size_t k = first; k < first + 6; ++k) sum += Front(landmarks, k);
  return sum / 6.0;
}

// An eye's points: outer or inner corner, two upper lid points, the other
// corner, two lower lid points (the lower ones in reverse order).
double EyeOpening(const FaceLandmarks& landmarks, std::size_t first) {
  const double height = 0.5 * (Between(landmarks, first + 1, first + 5) + Between(landmarks, first + 2, first + 4));
  return height / Between(landmarks, first, first + 3);
}

}  // namespace

const char* ProportionName(Proportion proportion) {
  switch (proportion) {
    case Proportion::kNoseLength: return "nose_length";
    case Proportion::kNoseWidth: return "nose_width";
    case Proportion::kEyeOpening: return "eye_opening";
    case Proportion::kMouthWidth: return "mouth_width";
    case Proportion::kLowerFace: return "lower_face";
    case Proportion::kFaceWidth: return "face_width";
  }
  return "?";
}

FaceProportions ProportionsOfLandmarks(const FaceLandmarks& landmarks) {
  namespace d = dlib68;
  FaceProportions p;
  p.eye_distance = glm::length(EyeCentre(landmarks, d::kRightEyeFirst) - EyeCentre(landmarks, d::kLeftEyeFirst));
  auto set = [&](Proportion which, double value) { p.ratios[static_cast<std::size_t>(which)] = value; };
  constexpr std::size_t kNasion = 27, kSubnasale = 33;
  set(Proportion::kNoseLength, Between(landmarks, kNasion, kSubnasale) / p.eye_distance);
  set(Proportion::kNoseWidth, Between(landmarks, d::kNostrilsFirst, d::kNostrilsLast) / p.eye_distance);
  set(Proportion::kEyeOpening,
      0.5 * (EyeOpening(landmarks, d::kRightEyeFirst) + EyeOpening(landmarks, d::kLeftEyeFirst)));
  set(Proportion::kMouthWidth, Between(landmarks, d::kOuterLipsFirst, d::kLeftMouthCorner) / p.eye_distance);
  set(Proportion::kLowerFace, Between(landmarks, kSubnasale, d::kChin) / p.eye_distance);
  set(Proportion::kFaceWidth, Between(landmarks, d::kJawFirst, d::kJawLast) / p.eye_distance);
  return p;
}

FaceProportions MeasureFaceProportions(LandmarkDetector& detector, const Mesh& mesh, LandmarkSource source) {
  const LandmarkResult result = detector.Detect(mesh);
  FaceLandmarks pixels;
  for (const glm::vec2& pixel : result.detected_pixels) pixels.points.emplace_back(pixel.x, -pixel.y, 0.0f);
  FaceProportions p = ProportionsOfLandmarks(source == LandmarkSource::kOnSurface ? result.landmarks : pixels);
  p.eyes_fitted = result.eyes_fitted;
  return p;
}

double ProportionReference::ZScore(Proportion p, double value) const {
  const auto i = static_cast<std::size_t>(p);
  return (value - mean[i]) / sd[i];
}

ProportionReference SummarizeProportions(std::vector<FaceProportions> faces) {
  ProportionReference reference;
  const auto n = static_cast<double>(faces.size());
  for (std::size_t i = 0; i < kProportionCount; ++i) {
    double sum = 0.0;
    for (const FaceProportions& face : faces) sum += face.ratios[i];
    reference.mean[i] = sum / n;
    double squares = 0.0;
    for (const FaceProportions& face : faces) squares += (face.ratios[i] - reference.mean[i]) * (face.ratios[i] - reference.mean[i]);
    reference.sd[i] = faces.size() > 1 ? std::sqrt(squares / (n - 1.0)) : 0.0;
  }
  reference.faces = std::move(faces);
  return reference;
}

ProportionReference IctProportionReference(LandmarkDetector& detector, const IctFaceModel& ict, int faces,
                                           std::uint32_t first_seed, LandmarkSource source) {
  std::vector<FaceProportions> measured;
  for (int i = 0; i < faces; ++i) {
    Mesh face = ict.head_mesh();
    face.positions = RandomIctFace(ict, first_seed + static_cast<std::uint32_t>(i));
    measured.push_back(MeasureFaceProportions(detector, face, source));
  }
  return SummarizeProportions(std::move(measured));
}

}  // namespace facerig::test
