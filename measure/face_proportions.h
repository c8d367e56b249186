// Face proportions from dlib's 68 points (issue 34): the mesh rendered and
// landmarked as the rig builder does (LandmarkDetector: a front render,
// dlib's 68 points lifted onto the surface, the eye points on the lid
// margins where the eyes are holes), then measured front-on (the points'
// x and y: the mesh faces +Z with +Y up) as ratios to the eye distance (the
// distance between the two eyes' centres, each the mean of its six points).
//
// Reference faces: ICT-FaceKit's random identities (neutral + the 20 identity
// modes with N(0, 1) weights, registration_targets.h), whose spread stands
// for the range of real faces a head should fall within.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/runtime/mesh.h"
#include "measure/registration_targets.h"

namespace facerig::test {

enum class Proportion : std::uint8_t {
  kNoseLength,   // nasion (27) to subnasale (33)
  kNoseWidth,    // the nostrils' outer points (31-35)
  kEyeOpening,   // each eye's height (the two lid pairs' mean) over its corner-to-corner width, both eyes' mean
  kMouthWidth,   // corner to corner (48-54)
  kLowerFace,    // subnasale (33) to the chin (8)
  kFaceWidth,    // the jaw line's ends at the ears (0-16)
};
inline constexpr std::size_t kProportionCount = 6;
inline constexpr std::array<Proportion, kProportionCount> kProportions = {
    Proportion::kNoseLength, Proportion::kNoseWidth, Proportion::kEyeOpening,
    Proportion::kMouthWidth, Proportion::kLowerFace, Proportion::kFaceWidth};
// Short names for tables and JSON keys ("nose_length", ...).
const char* ProportionName(Proportion proportion);

struct FaceProportions {
  std::array<double, kProportionCount> ratios{};  // by Proportion; eye opening is height/width
  double eye_distance = 0.0;                       // mesh units
  int eyes_fitted = 0;                             // eyes whose points went onto the lid margins
  double operator[](Proportion p) const { return ratios[static_cast<std::size_t>(p)]; }
};

// The proportions of 68 landmarks (dlib order, 3D, the face towards +Z, +Y up).
FaceProportions ProportionsOfLandmarks(const FaceLandmarks& landmarks);

// Which points are measured: the detector's result on the surface (the eye
// points on the lid margins where the eyes are holes), or dlib's own points
// in the render (no calibration, no eye fitting; the render is front-on
// within the detector's few degrees of refinement).
enum class LandmarkSource : std::uint8_t { kOnSurface, kDlibPixels };
// Detects the landmarks on `mesh` and measures them.
// \throw LandmarkDetectionError when dlib finds no face.
FaceProportions MeasureFaceProportions(LandmarkDetector& detector, const Mesh& mesh,
                                       LandmarkSource source = LandmarkSource::kOnSurface);

// Mean and standard deviation (n - 1) of each proportion over reference faces.
struct ProportionReference {
  std::array<double, kProportionCount> mean{}, sd{};
  std::vector<FaceProportions> faces;
  // How many reference SDs `value` lies from the mean (signed).
  double ZScore(Proportion p, double value) const;
};
ProportionReference SummarizeProportions(std::vector<FaceProportions> faces);

// ICT-FaceKit random faces (RandomIctFace with seeds first_seed, first_seed + 1, ...;
// the face and head region, ICT's own topology), measured.
ProportionReference IctProportionReference(LandmarkDetector& detector, const IctFaceModel& ict, int faces,
                                           std::uint32_t first_seed,
                                           LandmarkSource source = LandmarkSource::kOnSurface);

}  // namespace facerig::test
