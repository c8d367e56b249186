// Automatic 3D facial landmarks, as in automatic-correspondence facial
// deformation transfer (landmarks on a rendering, lifted to 3D): the mesh is rendered
// orthographically from the front with the project's CPU rasterizer, dlib's
// frontal face detector and 68-point shape predictor (Debian libdlib-data)
// find the 2D landmarks, and the z-buffer (triangle id + barycentrics per
// pixel) takes each one back to a 3D surface point.
//
// The front view comes from the mesh alone: +Y is taken as roughly up
// (+-25 degrees), the principal axis nearest to it refines up, the mirror
// symmetry plane gives the left-right axis, and the detector decides which
// side is the face; nearby rotations are then tried and the one the detector
// scores best is kept. Landmarks are in dlib / Multi-PIE order, in the mesh's
// own coordinates and units.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/offline/landmarks/dlib68.h"
#include "facerig/offline/landmarks/face_landmarks.h"
#include "facerig/offline/render/rasterizer.h"
#include "facerig/runtime/rig.h"

namespace facerig {

inline constexpr std::size_t kDlibLandmarkCount = dlib68::kCount;

struct LandmarkParams {
  std::filesystem::path shape_predictor = "/usr/share/dlib/shape_predictor_68_face_landmarks.dat";
  // Square render used to find the face (the whole mesh in view) and the
  // close-up render the 68 points are read from.
  int search_image_size = 256;
  int refine_image_size = 192;  // close-ups for the nearby rotations
  int landmark_image_size = 256;
  // Meshes with more triangles than this (scans) have their front view
  // estimated on a copy clustered to `proxy_cells` grid cells along the
  // longest side: bounded time and memory on million-vertex meshes.
  std::size_t proxy_triangle_limit = 200000;
  int proxy_cells = 150;
  // Nearby rotations tried around the estimated front view (yaw and pitch).
  float refine_step_degrees = 7.0f;
  bool refine_rotation = true;
  // Confidence of dlib's jaw points 0-16 (they follow the silhouette), and
  // the factor applied to a point snapped off a hole.
  float jaw_confidence = 0.3f;
  float snapped_confidence_factor = 0.5f;
  // A landmark whose surface lies farther behind its neighbourhood's front
  // surface than this (fraction of the face height) fell through a hole.
  float hole_depth_fraction = 0.08f;
  // Remove dlib's small systematic per-landmark offsets (brows, nostrils, ...)
  // against the ICT-FaceKit landmark vertices: a 2D table measured on random
  // ICT faces (tests/offline/landmarks_test.cpp, "[.calibrate]").
  bool calibrate = true;
  // Where an eye is a hole in the mesh, move its corner landmarks to the ends
  // of the hole's first principal axis. Off by default: with the calibration
  // on, it is slightly worse on ICT faces (docs/benchmarks.md,
  // "Measurements behind the defaults").
  bool correct_eye_corners = false;
  // Where an eye is a hole in the mesh near the detected eye, put all six of
  // its points on the hole's boundary, the lid margins (openings.h);
  // replaces correct_eye_corners for that eye. Why: on stylized heads dlib's
  // eyes come out too wide and their lower lids too high.
  bool fit_eyes_to_openings = true;
  // A lid point (dlib 37, 38, 40, 41, 43, 44, 46, 47) that lies farther than
  // off_skin_distance_fraction of the face height from the skin (the large
  // parts) landed on the eyeball or tear film seen through the opening: the
  // detector put the lid where the eye is, and pulling the template's lid
  // there would drag it across the opening onto the other lid. Where the eye
  // is a hole in the skin the point goes onto the hole's margin (with
  // fit_eyes_to_openings, confidence x snapped_confidence_factor); where it
  // is not, it is doubtful (LandmarkResult::doubtful_lids).
  float off_skin_distance_fraction = 0.002f;
};

struct LandmarkResult {
  FaceLandmarks landmarks;  // 68 points
  std::vector<glm::vec2> pixels;  // 2D landmarks in `image` (calibrated, snapped)
  std::vector<glm::vec2> detected_pixels;  // dlib's own output in `image`
  RasterView view;  // the close-up view the landmarks were read from
  RgbImage image;  // its render (the detector's input, in colour)
  double detector_score = 0.0;  // dlib's detection confidence in the chosen view
  int views_tried = 0;
  int snapped = 0;  // landmarks moved off a hole or a back face
  int corrected = 0;  // eye corners moved by the PCA correction
  int eyes_fitted = 0;  // eyes put on the mesh's eye openings (fit_eyes_to_openings)
  DoubtfulLidPoints doubtful_lids;  // left out of `landmarks`
  double seconds = 0.0;
};

// A face box dlib's frontal detector found in an image: pixels, left/top
// inclusive, right/bottom exclusive; score is the detection confidence.
struct ImageFaceBox {
  int left = 0;
  int top = 0;
  int right = 0;
  int bottom = 0;
  double score = 0.0;
  int width() const { return right - left; }
  int height() const { return bottom - top; }
};

// Loads dlib's detector and shape predictor once; Detect() reuses them.
// Not thread-safe (dlib keeps scratch buffers): one detector per thread.
class LandmarkDetector {
 public:
  // \throw IoError (kOpenFailed) when the shape predictor file cannot be read.
  explicit LandmarkDetector(const LandmarkParams& params = {});
  ~LandmarkDetector();
  LandmarkDetector(LandmarkDetector&&) noexcept;
  LandmarkDetector& operator=(LandmarkDetector&&) noexcept;

  // \throw InvalidInputError on an empty mesh, NaN coordinates or indices out of range.
  // \throw LandmarkDetectionError when no view shows a face (the message
  //        suggests a landmark file).
  LandmarkResult Detect(const Mesh& mesh);

  const LandmarkParams& params() const;

  // Every face box in a photograph (grey-scale conversion as ToGray), best score first.
  std::vector<ImageFaceBox> DetectFaceBoxes(const RgbImage& image);
  // dlib's 68 points (pixel centres) for the face in `box`.
  // \throw LandmarkDetectionError when the predictor does not return 68 points.
  std::vector<glm::vec2> PredictLandmarks(const RgbImage& image, const ImageFaceBox& box);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Every face box dlib's frontal detector finds in an image, best score first,
// as LandmarkDetector::DetectFaceBoxes but without the shape predictor (one
// detector per thread, made on first use): a photo's face can be found while
// another thread loads the predictor.
std::vector<ImageFaceBox> DetectFrontalFaceBoxes(const RgbImage& image);

// The render with the landmarks drawn (jaw points in a different colour).
RgbImage DrawLandmarks(const LandmarkResult& result);

// The largest landmark file read (68 points take about 4 kB).
inline constexpr std::uint64_t kMaxLandmarkFileBytes = std::uint64_t{16} << 20;

// JSON: {"points": [[x, y, z], ...], "confidence": [...], "indices": [...]}
// ("indices" optional: 0..n-1 when absent, i.e. dlib order). Writing is atomic.
// Reading goes through ReadInputText (input_file.h: a regular file of at most
// kMaxLandmarkFileBytes, JSON nested at most kMaxJsonNesting deep).
// \throw IoError naming the file (and the field) on unreadable or malformed
//        files, non-finite values, mismatched lengths or indices outside 0..67.
void WriteLandmarksJson(const std::filesystem::path& path, const FaceLandmarks& landmarks);
FaceLandmarks ReadLandmarksJson(const std::filesystem::path& path);
// The same from text; `name` names it in errors.
FaceLandmarks ParseLandmarksJson(std::string_view text, const std::string& name);

}  // namespace facerig
