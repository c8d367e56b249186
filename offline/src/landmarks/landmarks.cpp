// The only translation unit that includes dlib (slow to compile).
#include "facerig/offline/landmarks/landmarks.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <span>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include <dlib/image_processing.h>
#include <dlib/image_processing/frontal_face_detector.h>
#include <glm/geometric.hpp>

#include "facerig/offline/geometry/closest_point.h"
#include "facerig/offline/error.h"
#include "facerig/offline/geometry/mesh_components.h"
#include "facerig/offline/openings/eyes.h"
#include "facerig/offline/registration/rigid_align.h"
#include "facerig/offline/geometry/stats.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/rig_builder.h"
#include "landmarks/internal.h"

namespace facerig {

using namespace landmarks_detail;  // NOLINT: this file's own internal pieces

namespace {

// dlib decodes its face detector from a compressed string on every
// get_frontal_face_detector() call (a fifth of a second or more): decoded
// once per process, each user gets a copy (under a millisecond), since
// detection is not const.
dlib::frontal_face_detector FrontalFaceDetector() {
  static const dlib::frontal_face_detector decoded = dlib::get_frontal_face_detector();
  return decoded;
}

struct Detection {
  double score = -std::numeric_limits<double>::infinity();
  dlib::rectangle rect;
  bool found() const { return std::isfinite(score); }
};

// A view direction and the detector's verdict on the render along it.
struct Candidate {
  glm::vec3 forward;
  glm::vec3 up;
  RasterView view;
  Detection detection;
};

// The close-up the 68 points are read from: the detected face box fills half of it.
struct CloseUp {
  RasterView view;
  RasterBuffers buffers;
  RgbImage image;
  float face_height = 0.0f;  // world units
};

dlib::array2d<unsigned char> ToDlib(const RgbImage& image) {
  const std::vector<std::uint8_t> gray = ToGray(image);
  dlib::array2d<unsigned char> out(image.height, image.width);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      out[y][x] = gray[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                       static_cast<std::size_t>(x)];
    }
  }
  return out;
}

// Parts of at least this fraction of the largest part's area are skin (as
// BuildRigParams::registration_min_part_area).
constexpr double kSkinPartAreaFraction = 0.1;

constexpr std::size_t kLidPoints[] = {37, 38, 40, 41, 43, 44, 46, 47};

// Lid points off the skin: on the eyeball or tear film behind the opening
// (LandmarkParams::off_skin_distance_fraction).
LandmarkMask LidPointsOffSkin(const Mesh& mesh, std::span<const Triangle> skin, float face_height,
                              const LandmarkParams& params, const FaceLandmarks& landmarks) {
  LandmarkMask off_skin;
  if (skin.empty() || skin.size() == mesh.triangles.size()) return off_skin;  // one part: all of it is skin
  const float tolerance = params.off_skin_distance_fraction * face_height;
  // Eight points: a scan of the skin, no search structure.
  const auto on_skin = [&](const glm::vec3& p) {
    glm::vec3 barycentrics;
    for (const Triangle& t : skin) {
      const glm::vec3 q =
          ClosestPointOnTriangle(p, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]], barycentrics);
      if (glm::length(q - p) <= tolerance) return true;
    }
    return false;
  };
  for (const std::size_t k : kLidPoints) off_skin[k] = !on_skin(landmarks.points[k]);
  return off_skin;
}

// Where an eye is a hole in the mesh, its corners follow the hole, and lid
// points the detector put inside the hole go onto its margins; lid points off
// the skin with no margin to go to are doubtful (LandmarkResult).
void FitEyesToMesh(const Mesh& mesh, float face_height, const LandmarkParams& params, LandmarkResult& result) {
  // Holes in the skin only: ICT's eye layers have edges around the eye too.
  const std::vector<Triangle> skin = LargePartTriangles(mesh.positions, mesh.triangles, kSkinPartAreaFraction);
  FaceLandmarks& landmarks = result.landmarks;
  const LandmarkMask off_skin = LidPointsOffSkin(mesh, skin, face_height, params, landmarks);
  LandmarkMask on_margin;
  if (params.fit_eyes_to_openings) {
    const EyeOpeningFit fit = FitEyesToOpenings(mesh.positions, skin, landmarks.points, off_skin);
    result.eyes_fitted = fit.eyes;
    on_margin = fit.moved;
  }
  if (params.correct_eye_corners && result.eyes_fitted < 2) {
    result.corrected = CorrectEyeCorners(mesh.positions, mesh.triangles, landmarks.points);
  }
  result.doubtful_lids.confidence.assign(landmarks.confidence.size(), 0.0f);
  for (const std::size_t k : kLidPoints) {
    if (!off_skin[k]) continue;
    if (on_margin[k]) {
      landmarks.confidence[k] *= params.snapped_confidence_factor;
    } else {
      result.doubtful_lids.points[k] = true;
      result.doubtful_lids.confidence[k] = landmarks.confidence[k];
      landmarks.confidence[k] = 0.0f;
    }
  }
}

}  // namespace

struct LandmarkDetector::Impl {
  LandmarkParams params;
  // Set after the predictor is read: a photo is searched for its face on
  // another thread meanwhile, which decodes the detector.
  dlib::frontal_face_detector detector;
  dlib::shape_predictor predictor;

  // The mesh of the current Detect() call, with smooth normals for shading.
  Mesh shaded;
  int views_tried = 0;

  void PrepareShading(const Mesh& mesh) {
    shaded = Mesh{.positions = mesh.positions, .triangles = mesh.triangles};
    std::vector<glm::vec3> normals(mesh.positions.size());
    ComputeVertexNormals(mesh.positions, mesh.triangles, normals);
    for (const Triangle& t : mesh.triangles) {
      for (std::uint32_t v : t) shaded.corner_normals.push_back(normals[v]);
    }
    views_tried = 0;
  }

  RgbImage Render(const RasterView& view, RasterBuffers* buffers_out) {
    RasterBuffers buffers = Rasterize(shaded, view);
    RgbImage image = Shade(buffers, shaded, {}, view);
    if (buffers_out != nullptr) *buffers_out = std::move(buffers);
    return image;
  }

  Detection Detect(const RasterView& view) {
    ++views_tried;
    const dlib::array2d<unsigned char> image = ToDlib(Render(view, nullptr));
    std::vector<dlib::rect_detection> detections;
    detector(image, detections, 0.0);
    Detection best;
    for (const dlib::rect_detection& d : detections) {
      if (d.detection_confidence > best.score) {
        best.score = d.detection_confidence;
        best.rect = d.rect;
      }
    }
    return best;
  }

  // Which side is the face: the detector decides (both sides of the symmetry
  // plane, then the lateral directions should symmetry have failed). Views
  // frame all of `framed_positions`.
  Candidate FindFaceSide(std::span<const glm::vec3> framed_positions, const MeshFrame& frame);

  // Nearby rotations (yaw and pitch, both ways): keep the one the detector
  // likes best. Close-ups (the face box fills half the image) are cheaper to
  // render and scan than the whole mesh, and comparable with each other.
  Candidate RefineByCloseUps(const Candidate& centre);

  // Close-up on the detected face: its box fills half of the image.
  CloseUp RenderCloseUp(const Candidate& best);

  // dlib's 68 points on the close-up, as pixel centres.
  std::vector<glm::vec2> PredictLandmarkPixels(const RgbImage& image);
  std::vector<glm::vec2> PredictInBox(const dlib::array2d<unsigned char>& image, const dlib::rectangle& face_box);
};

Candidate LandmarkDetector::Impl::FindFaceSide(std::span<const glm::vec3> framed_positions, const MeshFrame& frame) {
  const glm::vec3 facing = glm::normalize(glm::cross(frame.lateral, frame.up));
  Candidate best{};
  auto consider = [&](glm::vec3 forward, glm::vec3 up) {
    Candidate c{forward, up, FrontView(framed_positions, forward, up, params.search_image_size), {}};
    c.detection = Detect(c.view);
    if (c.detection.score > best.detection.score) best = c;
    return c.detection.found();
  };
  // dlib does not find faces on the back of a head: a confident hit on the
  // first side settles it.
  const bool facing_found = consider(facing, frame.up);
  const bool behind_found = facing_found && best.detection.score >= 0.5 ? false : consider(-facing, frame.up);
  if (!facing_found && !behind_found) {
    consider(frame.lateral, frame.up);
    consider(-frame.lateral, frame.up);
  }
  if (!best.detection.found()) {
    throw LandmarkDetectionError(
        "landmarks: the face detector found no face in any view of the mesh (is it a face, roughly "
        "upright with +Y up?); give the landmarks in a file instead (--landmarks LM.json: {\"points\": "
        "[[x, y, z], ...]} in dlib's 68-point order, or a subset with \"indices\")");
  }
  return best;
}

Candidate LandmarkDetector::Impl::RefineByCloseUps(const Candidate& centre) {
  Candidate best = centre;
  const float scale = PixelsPerUnit(centre.view);
  const dlib::rectangle& box = centre.detection.rect;
  const glm::vec3 face_centre = Unproject(
      centre.view, {0.5f * static_cast<float>(box.left() + box.right() + 1),
                    0.5f * static_cast<float>(box.top() + box.bottom() + 1)});
  const float face_size = static_cast<float>(std::max(box.width(), box.height())) / scale;
  bool have_close_up = false;
  auto consider_close_up = [&](glm::vec3 forward, glm::vec3 up) {
    Candidate c{forward, up, FaceView(forward, up, face_centre, face_size, params.refine_image_size), {}};
    c.detection = Detect(c.view);
    // The first close-up replaces the whole-mesh view (scores compare
    // only between views framed alike).
    if (c.detection.found() && (!have_close_up || c.detection.score > best.detection.score)) {
      best = c;
      have_close_up = true;
    }
  };
  const auto step = static_cast<float>(params.refine_step_degrees * kPi / 180.0);
  const glm::vec3 right = glm::normalize(glm::cross(centre.up, centre.forward));
  consider_close_up(centre.forward, centre.up);
  for (float sign : {-1.0f, 1.0f}) {
    consider_close_up(Rotate(centre.forward, centre.up, sign * step), centre.up);  // yaw
    consider_close_up(Rotate(centre.forward, right, sign * step), Rotate(centre.up, right, sign * step));  // pitch
  }
  return best;
}

CloseUp LandmarkDetector::Impl::RenderCloseUp(const Candidate& best) {
  const RasterView& search = best.view;
  const float search_scale = PixelsPerUnit(search);
  const dlib::rectangle& rect = best.detection.rect;
  const glm::vec2 rect_centre(0.5f * static_cast<float>(rect.left() + rect.right() + 1),
                              0.5f * static_cast<float>(rect.top() + rect.bottom() + 1));
  const float rect_size = static_cast<float>(std::max(rect.width(), rect.height()));
  CloseUp close_up;
  close_up.view = search;
  close_up.view.centre = Unproject(search, rect_centre);
  close_up.view.half_extent = rect_size / search_scale;
  close_up.view.width = params.landmark_image_size;
  close_up.view.height = params.landmark_image_size;
  close_up.image = Render(close_up.view, &close_up.buffers);
  close_up.face_height = rect_size / search_scale;
  return close_up;
}

std::vector<glm::vec2> LandmarkDetector::Impl::PredictLandmarkPixels(const RgbImage& image) {
  const long quarter = params.landmark_image_size / 4;
  return PredictInBox(ToDlib(image), dlib::rectangle(quarter, quarter, 3 * quarter, 3 * quarter));
}

std::vector<glm::vec2> LandmarkDetector::Impl::PredictInBox(const dlib::array2d<unsigned char>& image,
                                                            const dlib::rectangle& face_box) {
  const dlib::full_object_detection shape = predictor(image, face_box);
  if (shape.num_parts() != kDlibLandmarkCount) {
    throw LandmarkDetectionError("landmarks: the shape predictor did not return 68 points");
  }
  std::vector<glm::vec2> pixels(kDlibLandmarkCount);
  for (std::size_t k = 0; k < kDlibLandmarkCount; ++k) {
    const dlib::point part = shape.part(static_cast<unsigned long>(k));
    pixels[k] = {static_cast<float>(part.x()) + 0.5f, static_cast<float>(part.y()) + 0.5f};
  }
  return pixels;
}

LandmarkDetector::LandmarkDetector(const LandmarkParams& params) : impl_(std::make_unique<Impl>()) {
  impl_->params = params;
  std::error_code type_error;
  if (std::filesystem::exists(params.shape_predictor, type_error) &&
      !std::filesystem::is_regular_file(params.shape_predictor, type_error)) {
    // Opening a FIFO would block: only a regular file is read.
    throw IoError(IoErrorKind::kOpenFailed, params.shape_predictor.string(),
                  "is not a regular file, so not dlib's 68-point shape predictor");
  }
  std::ifstream probe(params.shape_predictor, std::ios::binary);
  if (!probe) {
    throw IoError(IoErrorKind::kOpenFailed, params.shape_predictor.string(),
                  "cannot read dlib's 68-point shape predictor (Debian: apt install libdlib-data)");
  }
  probe.close();
  try {
    dlib::deserialize(params.shape_predictor.string()) >> impl_->predictor;
  } catch (const dlib::error& e) {
    throw IoError(IoErrorKind::kParse, params.shape_predictor.string(),
                  std::string("not a dlib shape predictor: ") + e.what());
  }
  impl_->detector = FrontalFaceDetector();
}

LandmarkDetector::~LandmarkDetector() = default;
LandmarkDetector::LandmarkDetector(LandmarkDetector&&) noexcept = default;
LandmarkDetector& LandmarkDetector::operator=(LandmarkDetector&&) noexcept = default;
const LandmarkParams& LandmarkDetector::params() const { return impl_->params; }

namespace {

std::vector<ImageFaceBox> FaceBoxes(dlib::frontal_face_detector& detector, const RgbImage& image) {
  std::vector<dlib::rect_detection> detections;
  detector(ToDlib(image), detections, 0.0);
  std::vector<ImageFaceBox> boxes;
  for (const dlib::rect_detection& d : detections) {
    boxes.push_back({static_cast<int>(d.rect.left()), static_cast<int>(d.rect.top()),
                     static_cast<int>(d.rect.right()) + 1, static_cast<int>(d.rect.bottom()) + 1,
                     d.detection_confidence});
  }
  std::stable_sort(boxes.begin(), boxes.end(),
                   [](const ImageFaceBox& a, const ImageFaceBox& b) { return a.score > b.score; });
  return boxes;
}

}  // namespace

std::vector<ImageFaceBox> LandmarkDetector::DetectFaceBoxes(const RgbImage& image) {
  return FaceBoxes(impl_->detector, image);
}

std::vector<ImageFaceBox> DetectFrontalFaceBoxes(const RgbImage& image) {
  thread_local dlib::frontal_face_detector detector = FrontalFaceDetector();
  return FaceBoxes(detector, image);
}

std::vector<glm::vec2> LandmarkDetector::PredictLandmarks(const RgbImage& image, const ImageFaceBox& box) {
  return impl_->PredictInBox(ToDlib(image), dlib::rectangle(box.left, box.top, box.right - 1, box.bottom - 1));
}

LandmarkResult LandmarkDetector::Detect(const Mesh& mesh) {
  const auto start = std::chrono::steady_clock::now();
  CheckMesh(mesh, "landmarks");
  Impl& impl = *impl_;
  const LandmarkParams& params = impl.params;
  impl.PrepareShading(mesh);
  const FramingMesh framing = PrepareFraming(mesh, params.proxy_triangle_limit, params.proxy_cells);
  Candidate best = impl.FindFaceSide(framing.FramedPositions(mesh.positions), framing.frame);
  if (params.refine_rotation && params.refine_step_degrees > 0.0f) best = impl.RefineByCloseUps(best);

  CloseUp close_up = impl.RenderCloseUp(best);
  LandmarkResult result;
  result.detected_pixels = impl.PredictLandmarkPixels(close_up.image);
  LiftedLandmarks lifted =
      LiftLandmarks(mesh, close_up.view, close_up.buffers, close_up.face_height, result.detected_pixels, params);
  result.landmarks = std::move(lifted.landmarks);
  result.pixels = std::move(lifted.pixels);
  result.snapped = lifted.snapped;
  result.view = close_up.view;
  result.image = std::move(close_up.image);
  result.detector_score = best.detection.score;
  FitEyesToMesh(mesh, close_up.face_height, params, result);
  result.views_tried = impl.views_tried;
  result.seconds = SecondsSince(start);
  return result;
}

}  // namespace facerig
