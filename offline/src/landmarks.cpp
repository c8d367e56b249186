// The only translation unit that includes dlib (slow to compile).
#include "facerig/offline/landmarks.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <system_error>

#include <Eigen/Eigenvalues>
#include <dlib/image_processing.h>
#include <dlib/image_processing/frontal_face_detector.h>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <nlohmann/json.hpp>

#include "eye_openings.h"
#include "facerig/offline/closest_point.h"
#include "facerig/offline/registration_error.h"
#include "facerig/offline/rigid_align.h"
#include "facerig/offline/stats.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/rig_builder.h"

namespace facerig {
namespace {

constexpr double kPi = 3.14159265358979323846;

glm::vec3 Rotate(glm::vec3 v, glm::vec3 axis, float radians) {
  // Rodrigues.
  const float c = std::cos(radians), s = std::sin(radians);
  return v * c + glm::cross(axis, v) * s + axis * glm::dot(axis, v) * (1.0f - c);
}

// The mesh's own estimate of where its face is: centre, up and the normal of
// the mirror-symmetry plane (the left-right axis).
struct MeshFrame {
  glm::vec3 centre{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  glm::vec3 lateral{1.0f, 0.0f, 0.0f};
};

MeshFrame EstimateFrame(std::span<const glm::vec3> positions, std::span<const Triangle> triangles,
                        const ClosestPointQuery& surface) {
  // Area-weighted moments: independent of how densely each region is meshed.
  double area_sum = 0.0;
  glm::dvec3 mean(0.0);
  for (const Triangle& t : triangles) {
    const glm::vec3 a = positions[t[0]], b = positions[t[1]], c = positions[t[2]];
    const double area = 0.5 * static_cast<double>(glm::length(glm::cross(b - a, c - a)));
    area_sum += area;
    mean += area * glm::dvec3((a + b + c) / 3.0f);
  }
  if (!(area_sum > 0.0)) throw InvalidInputError("landmarks: every triangle of the mesh is degenerate");
  mean /= area_sum;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Triangle& t : triangles) {
    const glm::vec3 a = positions[t[0]], b = positions[t[1]], c = positions[t[2]];
    const double area = 0.5 * static_cast<double>(glm::length(glm::cross(b - a, c - a)));
    const glm::dvec3 d = glm::dvec3((a + b + c) / 3.0f) - mean;
    const Eigen::Vector3d e(d.x, d.y, d.z);
    covariance += area * e * e.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  MeshFrame frame;
  frame.centre = glm::vec3(mean);
  // Up: the principal axis nearest to +Y (the input is roughly upright).
  int best_axis = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(eigen.eigenvectors()(1, k)) > std::abs(eigen.eigenvectors()(1, best_axis))) best_axis = k;
  }
  glm::vec3 up(static_cast<float>(eigen.eigenvectors()(0, best_axis)),
               static_cast<float>(eigen.eigenvectors()(1, best_axis)),
               static_cast<float>(eigen.eigenvectors()(2, best_axis)));
  if (up.y < 0.0f) up = -up;
  // A principal axis more than 35 degrees from +Y is not the head's up axis
  // (e.g. a face mask wider than tall): keep +Y.
  frame.up = up.y > std::cos(static_cast<float>(35.0 * kPi / 180.0)) ? glm::normalize(up) : glm::vec3(0, 1, 0);

  // Symmetry plane through the centre containing up: the lateral direction
  // whose mirror image of the surface lies closest to the surface.
  const glm::vec3 a = glm::normalize(glm::cross(frame.up, std::abs(frame.up.z) < 0.9f ? glm::vec3(0, 0, 1)
                                                                                         : glm::vec3(1, 0, 0)));
  const glm::vec3 b = glm::cross(frame.up, a);
  // Only vertices of triangles: stray points are not surface.
  std::vector<std::uint8_t> used(positions.size(), 0);
  for (const Triangle& t : triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
  std::vector<glm::vec3> samples;
  const std::size_t stride = std::max<std::size_t>(1, positions.size() / 300);
  for (std::size_t v = 0; v < positions.size(); v += stride) {
    if (used[v]) samples.push_back(positions[v]);
  }
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (!used[v]) continue;
    lo = glm::min(lo, positions[v]);
    hi = glm::max(hi, positions[v]);
  }
  const float cap = 0.05f * glm::length(hi - lo);
  auto asymmetry = [&](float theta) {
    const glm::vec3 lateral = std::cos(theta) * a + std::sin(theta) * b;
    double sum = 0.0;
    for (const glm::vec3& p : samples) {
      const glm::vec3 mirrored = p - 2.0f * glm::dot(p - frame.centre, lateral) * lateral;
      sum += static_cast<double>(std::min(surface.Find(mirrored, cap).distance, cap));
    }
    return sum;
  };
  float best_theta = 0.0f;
  double best = std::numeric_limits<double>::infinity();
  constexpr int kCoarse = 12;
  for (int i = 0; i < kCoarse; ++i) {
    const auto theta = static_cast<float>(kPi * i / kCoarse);
    const double score = asymmetry(theta);
    if (score < best) {
      best = score;
      best_theta = theta;
    }
  }
  const float coarse_step = static_cast<float>(kPi / kCoarse);
  const float centre_theta = best_theta;
  for (int i = -3; i <= 3; ++i) {
    const float theta = centre_theta + coarse_step * static_cast<float>(i) / 4.0f;
    const double score = asymmetry(theta);
    if (score < best) {
      best = score;
      best_theta = theta;
    }
  }
  frame.lateral = std::cos(best_theta) * a + std::sin(best_theta) * b;
  return frame;
}

// A coarse stand-in for a large mesh (vertex clustering on a grid of
// `cells` cells along the longest side): the front-view estimate only needs
// the overall shape, and a million-vertex scan would otherwise cost a
// closest-point structure of millions of triangles. Vertices no triangle
// uses are left out, so stray points do not count as surface.
struct ProxyMesh {
  std::vector<glm::vec3> positions;
  std::vector<Triangle> triangles;
};

ProxyMesh ClusterMesh(std::span<const glm::vec3> positions, std::span<const Triangle> triangles, int cells) {
  std::vector<std::uint8_t> used(positions.size(), 0);
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const Triangle& t : triangles) {
    for (std::uint32_t v : t) {
      used[v] = 1;
      lo = glm::min(lo, positions[v]);
      hi = glm::max(hi, positions[v]);
    }
  }
  const glm::vec3 extent = hi - lo;
  const float cell = std::max({extent.x, extent.y, extent.z}) / static_cast<float>(cells);
  // (cell key, vertex), sorted: vertices of one cell become one proxy vertex.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
  keyed.reserve(positions.size());
  for (std::uint32_t v = 0; v < positions.size(); ++v) {
    if (!used[v]) continue;
    const glm::vec3 q = cell > 0.0f ? (positions[v] - lo) / cell : glm::vec3(0.0f);
    const auto ix = static_cast<std::uint64_t>(std::min(q.x, static_cast<float>(cells)));
    const auto iy = static_cast<std::uint64_t>(std::min(q.y, static_cast<float>(cells)));
    const auto iz = static_cast<std::uint64_t>(std::min(q.z, static_cast<float>(cells)));
    keyed.emplace_back((ix << 42) | (iy << 21) | iz, v);
  }
  std::sort(keyed.begin(), keyed.end());
  constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::uint32_t> proxy_of(positions.size(), kNone);
  ProxyMesh proxy;
  std::vector<float> members;
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i].first != keyed[i - 1].first) {
      proxy.positions.emplace_back(0.0f);
      members.push_back(0.0f);
    }
    proxy.positions.back() += positions[keyed[i].second];
    members.back() += 1.0f;
    proxy_of[keyed[i].second] = static_cast<std::uint32_t>(proxy.positions.size() - 1);
  }
  for (std::size_t p = 0; p < proxy.positions.size(); ++p) proxy.positions[p] /= members[p];
  for (const Triangle& t : triangles) {
    const Triangle mapped{proxy_of[t[0]], proxy_of[t[1]], proxy_of[t[2]]};
    if (mapped[0] != mapped[1] && mapped[1] != mapped[2] && mapped[0] != mapped[2]) proxy.triangles.push_back(mapped);
  }
  return proxy;
}

// Orthographic view of the face: `centre` in the middle, the face (size
// `face_size`, world units) filling half of the image.
RasterView FaceView(glm::vec3 forward, glm::vec3 up, glm::vec3 centre, float face_size, int size) {
  forward = glm::normalize(forward);
  up = glm::normalize(up - glm::dot(up, forward) * forward);
  const glm::vec3 right = glm::cross(up, forward);
  RasterView view;
  for (int c = 0; c < 3; ++c) {
    view.rotation[c][0] = right[c];
    view.rotation[c][1] = up[c];
    view.rotation[c][2] = forward[c];
  }
  view.centre = centre;
  view.half_extent = face_size;
  view.width = size;
  view.height = size;
  return view;
}

glm::vec3 ViewAxis(const RasterView& view, int row) {
  return {view.rotation[0][row], view.rotation[1][row], view.rotation[2][row]};
}

// Orthographic view looking at the face along -forward, up as given, framing
// the whole mesh.
RasterView FrontView(std::span<const glm::vec3> positions, glm::vec3 forward, glm::vec3 up, int size) {
  RasterView view = FaceView(forward, up, glm::vec3(0.0f), 1.0f, size);
  const glm::vec3 right = ViewAxis(view, 0);
  const glm::vec3 view_up = ViewAxis(view, 1);
  glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const glm::vec3& p : positions) {
    const glm::vec2 q(glm::dot(p, right), glm::dot(p, view_up));
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  const glm::vec2 mid = 0.5f * (lo + hi);
  view.centre = mid.x * right + mid.y * view_up;
  view.half_extent = 0.52f * std::max(hi.x - lo.x, hi.y - lo.y);
  return view;
}

float PixelsPerUnit(const RasterView& view) { return 0.5f * static_cast<float>(view.height) / view.half_extent; }

// World point on the image plane through the centre, under pixel (x, y).
glm::vec3 Unproject(const RasterView& view, glm::vec2 pixel) {
  const float scale = PixelsPerUnit(view);
  const float cx = (pixel.x - 0.5f * static_cast<float>(view.width)) / scale;
  const float cy = (0.5f * static_cast<float>(view.height) - pixel.y) / scale;
  return view.centre + cx * ViewAxis(view, 0) + cy * ViewAxis(view, 1);
}

// dlib's 68 points minus the ICT-FaceKit landmark vertices, in the close-up
// view (x right, y down), as fractions of the detected face box: subtracted
// from each detection when LandmarkParams::calibrate. Measured on 12 random
// ICT faces (seeds 101-112, re-meshed, rotated; the tests use other seeds).
constexpr std::array<std::array<float, 2>, kDlibLandmarkCount> kCalibration{{
#include "landmark_calibration.inc"
}};

struct Detection {
  double score = -std::numeric_limits<double>::infinity();
  dlib::rectangle rect;
  bool found() const { return std::isfinite(score); }
};

}  // namespace

struct LandmarkDetector::Impl {
  LandmarkParams params;
  dlib::frontal_face_detector detector = dlib::get_frontal_face_detector();
  dlib::shape_predictor predictor;

  // The mesh of the current Detect() call, with smooth normals for shading.
  Mesh shaded;
  int views_tried = 0;

  RgbImage Render(const RasterView& view, RasterBuffers* buffers_out) {
    RasterBuffers buffers = Rasterize(shaded, view);
    RgbImage image = Shade(buffers, shaded, {}, view);
    if (buffers_out != nullptr) *buffers_out = std::move(buffers);
    return image;
  }

  static dlib::array2d<unsigned char> ToDlib(const RgbImage& image) {
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
};

LandmarkDetector::LandmarkDetector(const LandmarkParams& params) : impl_(std::make_unique<Impl>()) {
  impl_->params = params;
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
}

LandmarkDetector::~LandmarkDetector() = default;
LandmarkDetector::LandmarkDetector(LandmarkDetector&&) noexcept = default;
LandmarkDetector& LandmarkDetector::operator=(LandmarkDetector&&) noexcept = default;
const LandmarkParams& LandmarkDetector::params() const { return impl_->params; }

LandmarkResult LandmarkDetector::Detect(const Mesh& mesh) {
  const auto start = std::chrono::steady_clock::now();
  CheckMesh(mesh, "landmarks");
  const std::span<const glm::vec3> positions = mesh.positions;
  const std::span<const Triangle> triangles = mesh.triangles;
  Impl& impl = *impl_;
  const LandmarkParams& params = impl.params;
  impl.shaded = Mesh{.positions = mesh.positions, .triangles = mesh.triangles};
  std::vector<glm::vec3> normals(positions.size());
  ComputeVertexNormals(positions, triangles, normals);
  for (const Triangle& t : triangles) {
    for (std::uint32_t v : t) impl.shaded.corner_normals.push_back(normals[v]);
  }
  impl.views_tried = 0;

  // The front-view estimate and the whole-mesh framing only need the overall
  // shape: a large mesh (a million-vertex scan) is replaced by a clustered
  // copy, so the closest-point structure stays small. Vertices no triangle
  // uses (stray points) never count.
  ProxyMesh proxy;
  const bool use_proxy = triangles.size() > params.proxy_triangle_limit;
  if (use_proxy) {
    proxy = ClusterMesh(positions, triangles, params.proxy_cells);
    if (proxy.triangles.empty()) throw InvalidInputError("landmarks: every triangle of the mesh is degenerate");
  } else {
    std::vector<std::uint8_t> used(positions.size(), 0);
    for (const Triangle& t : triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
    if (std::find(used.begin(), used.end(), 0) != used.end()) {
      for (std::size_t v = 0; v < positions.size(); ++v) {
        if (used[v]) proxy.positions.push_back(positions[v]);
      }
    }
  }
  const std::span<const glm::vec3> frame_positions =
      use_proxy ? std::span<const glm::vec3>(proxy.positions) : positions;
  const std::span<const Triangle> frame_triangles = use_proxy ? std::span<const Triangle>(proxy.triangles) : triangles;
  const std::span<const glm::vec3> framed_positions =
      proxy.positions.empty() ? positions : std::span<const glm::vec3>(proxy.positions);
  const ClosestPointQuery surface(Mesh{.positions = {frame_positions.begin(), frame_positions.end()},
                                       .triangles = {frame_triangles.begin(), frame_triangles.end()}});
  const MeshFrame frame = EstimateFrame(frame_positions, frame_triangles, surface);
  const glm::vec3 facing = glm::normalize(glm::cross(frame.lateral, frame.up));

  // Which side is the face: the detector decides (both sides of the symmetry
  // plane, then the lateral directions should symmetry have failed).
  struct Candidate {
    glm::vec3 forward;
    glm::vec3 up;
    RasterView view;
    Detection detection;
  };
  Candidate best{};
  auto consider = [&](glm::vec3 forward, glm::vec3 up) {
    Candidate c{forward, up, FrontView(framed_positions, forward, up, params.search_image_size), {}};
    c.detection = impl.Detect(c.view);
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

  // Nearby rotations: keep the one the detector likes best.
  if (params.refine_rotation && params.refine_step_degrees > 0.0f) {
    // Close-ups (the face box fills half the image): cheaper to render and
    // scan than the whole mesh, and comparable with each other.
    const Candidate centre = best;
    const float scale = PixelsPerUnit(centre.view);
    const dlib::rectangle& box = centre.detection.rect;
    const glm::vec3 face_centre = Unproject(
        centre.view, {0.5f * static_cast<float>(box.left() + box.right() + 1),
                      0.5f * static_cast<float>(box.top() + box.bottom() + 1)});
    const float face_size = static_cast<float>(std::max(box.width(), box.height())) / scale;
    bool have_close_up = false;
    auto consider_close_up = [&](glm::vec3 forward, glm::vec3 up) {
      Candidate c{forward, up, FaceView(forward, up, face_centre, face_size, params.refine_image_size), {}};
      c.detection = impl.Detect(c.view);
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
  }

  // Close-up on the detected face: its box fills half of the image.
  const RasterView& search = best.view;
  const float search_scale = PixelsPerUnit(search);
  const dlib::rectangle& rect = best.detection.rect;
  const glm::vec2 rect_centre(0.5f * static_cast<float>(rect.left() + rect.right() + 1),
                              0.5f * static_cast<float>(rect.top() + rect.bottom() + 1));
  const float rect_size = static_cast<float>(std::max(rect.width(), rect.height()));
  RasterView view = search;
  view.centre = Unproject(search, rect_centre);
  view.half_extent = rect_size / search_scale;
  view.width = params.landmark_image_size;
  view.height = params.landmark_image_size;
  RasterBuffers buffers;
  LandmarkResult result;
  result.image = impl.Render(view, &buffers);
  result.view = view;
  result.detector_score = best.detection.score;
  const long quarter = params.landmark_image_size / 4;
  const dlib::rectangle face_box(quarter, quarter, 3 * quarter, 3 * quarter);
  const dlib::full_object_detection shape = impl.predictor(Impl::ToDlib(result.image), face_box);
  if (shape.num_parts() != kDlibLandmarkCount) {
    throw LandmarkDetectionError("landmarks: the shape predictor did not return 68 points");
  }

  // 2D -> 3D through the z-buffer.
  const float scale = PixelsPerUnit(view);
  const float face_height = rect_size / search_scale;
  const float hole_depth = params.hole_depth_fraction * face_height;
  const glm::vec3 view_forward = ViewAxis(view, 2);
  const int w = view.width, h = view.height;
  auto usable = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= w || y >= h) return false;
    const std::size_t i = buffers.index(x, y);
    return buffers.triangle_ids[i] != kNoTriangle && !buffers.back_facing[i];
  };
  // The nearest front surface around a pixel (largest depth = nearest).
  auto front_depth = [&](int x0, int y0, int radius) {
    float front = -std::numeric_limits<float>::infinity();
    for (int y = y0 - radius; y <= y0 + radius; ++y) {
      for (int x = x0 - radius; x <= x0 + radius; ++x) {
        if (usable(x, y)) front = std::max(front, buffers.depths[buffers.index(x, y)]);
      }
    }
    return front;
  };
  const int window = std::max(2, static_cast<int>(0.03f * face_height * scale));
  result.landmarks.points.resize(kDlibLandmarkCount);
  result.landmarks.confidence.resize(kDlibLandmarkCount);
  result.landmarks.indices.resize(kDlibLandmarkCount);
  result.pixels.resize(kDlibLandmarkCount);
  result.detected_pixels.resize(kDlibLandmarkCount);
  for (std::size_t k = 0; k < kDlibLandmarkCount; ++k) {
    const dlib::point part = shape.part(static_cast<unsigned long>(k));
    glm::vec2 pixel(static_cast<float>(part.x()) + 0.5f, static_cast<float>(part.y()) + 0.5f);
    result.detected_pixels[k] = pixel;
    if (params.calibrate) {
      const float box = 0.5f * static_cast<float>(params.landmark_image_size);
      pixel -= box * glm::vec2(kCalibration[k][0], kCalibration[k][1]);
    }
    int px = static_cast<int>(std::floor(pixel.x)), py = static_cast<int>(std::floor(pixel.y));
    const float front = front_depth(px, py, window);
    const bool good = usable(px, py) && buffers.depths[buffers.index(px, py)] >= front - hole_depth;
    float confidence = k < 17 ? params.jaw_confidence : 1.0f;
    if (!good) {
      // Ring search outwards for the nearest front-facing pixel on the front surface.
      const int max_radius = std::max(w, h) / 4;
      int found_x = -1, found_y = -1;
      float found_d2 = std::numeric_limits<float>::infinity();
      for (int r = 1; r <= max_radius && found_x < 0; ++r) {
        for (int y = py - r; y <= py + r; ++y) {
          for (int x = px - r; x <= px + r; ++x) {
            if (std::max(std::abs(x - px), std::abs(y - py)) != r || !usable(x, y)) continue;
            if (std::isfinite(front) && buffers.depths[buffers.index(x, y)] < front - hole_depth) continue;
            const float d2 = static_cast<float>((x - px) * (x - px) + (y - py) * (y - py));
            if (d2 < found_d2) {
              found_d2 = d2;
              found_x = x;
              found_y = y;
            }
          }
        }
      }
      if (found_x < 0) {
        throw LandmarkDetectionError("landmarks: landmark " + std::to_string(k) +
                                     " has no surface near it; give the landmarks in a file (--landmarks)");
      }
      px = found_x;
      py = found_y;
      pixel = {static_cast<float>(px) + 0.5f, static_cast<float>(py) + 0.5f};
      confidence *= params.snapped_confidence_factor;
      ++result.snapped;
    }
    // Sub-pixel: intersect the viewing ray with the plane of the triangle under the pixel.
    const std::size_t i = buffers.index(px, py);
    const Triangle& t = triangles[static_cast<std::size_t>(buffers.triangle_ids[i])];
    const glm::vec3 b = buffers.barycentrics[i];
    glm::vec3 point = b.x * positions[t[0]] + b.y * positions[t[1]] + b.z * positions[t[2]];
    const glm::vec3 normal = glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
    const glm::vec3 origin = Unproject(view, pixel);
    const float denominator = glm::dot(normal, view_forward);
    if (std::abs(denominator) > 0.2f * glm::length(normal)) {
      const float along = glm::dot(normal, point - origin) / denominator;
      const glm::vec3 on_plane = origin + along * view_forward;
      if (glm::length(on_plane - point) < 1.5f / scale) point = on_plane;
    }
    result.landmarks.points[k] = point;
    result.landmarks.confidence[k] = confidence;
    result.landmarks.indices[k] = static_cast<std::uint32_t>(k);
    result.pixels[k] = pixel;
  }
  if (params.fit_eyes_to_openings) {
    result.eyes_fitted = FitEyesToOpenings(positions, triangles, result.landmarks.points);
  }
  if (params.correct_eye_corners && result.eyes_fitted < 2) {
    result.corrected = CorrectEyeCorners(positions, triangles, result.landmarks.points);
  }
  result.views_tried = impl.views_tried;
  result.seconds = SecondsSince(start);
  return result;
}

RgbImage DrawLandmarks(const LandmarkResult& result) {
  RgbImage image = result.image;
  auto put = [&](int x, int y, std::array<std::uint8_t, 3> colour) {
    if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
    const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                               static_cast<std::size_t>(x));
    for (std::size_t c = 0; c < 3; ++c) image.pixels[i + c] = colour[c];
  };
  for (std::size_t k = 0; k < result.pixels.size(); ++k) {
    const bool jaw = k < 17;
    const bool snapped = k < result.landmarks.confidence.size() &&
                         result.landmarks.confidence[k] < (jaw ? 0.999f * 0.3f : 0.999f);
    const std::array<std::uint8_t, 3> colour = snapped ? std::array<std::uint8_t, 3>{255, 60, 60}
                                               : jaw   ? std::array<std::uint8_t, 3>{255, 210, 0}
                                                       : std::array<std::uint8_t, 3>{40, 255, 80};
    const int cx = static_cast<int>(std::floor(result.pixels[k].x));
    const int cy = static_cast<int>(std::floor(result.pixels[k].y));
    for (int d = -2; d <= 2; ++d) {
      put(cx + d, cy, colour);
      put(cx, cy + d, colour);
    }
  }
  return image;
}

void WriteLandmarksJson(const std::filesystem::path& path, const FaceLandmarks& landmarks) {
  if (landmarks.confidence.size() != landmarks.points.size() ||
      (!landmarks.indices.empty() && landmarks.indices.size() != landmarks.points.size())) {
    throw IoError(IoErrorKind::kWriteFailed, path.string(), "landmark points, confidences and indices differ in length");
  }
  nlohmann::json json;
  json["format"] = "facerig-landmarks";
  json["version"] = 1;
  json["order"] = "dlib-68";
  nlohmann::json points = nlohmann::json::array();
  for (const glm::vec3& p : landmarks.points) points.push_back({p.x, p.y, p.z});
  json["points"] = std::move(points);
  json["confidence"] = landmarks.confidence;
  if (!landmarks.indices.empty()) json["indices"] = landmarks.indices;
  const std::filesystem::path temporary = path.string() + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << json.dump(1) << "\n";
    if (!out) throw IoError(IoErrorKind::kWriteFailed, temporary.string(), "cannot write the landmark file");
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::filesystem::remove(temporary, error);
    throw IoError(IoErrorKind::kWriteFailed, path.string(), "cannot rename the landmark file into place");
  }
}

FaceLandmarks ReadLandmarksJson(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(IoErrorKind::kOpenFailed, path.string(), "cannot open the landmark file");
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::exception& e) {
    throw IoError(IoErrorKind::kParse, path.string(), std::string("not JSON: ") + e.what());
  }
  FaceLandmarks landmarks;
  try {
    if (!json.is_object() || !json.contains("points") || !json["points"].is_array()) {
      throw IoError(IoErrorKind::kParse, path.string(), "expected an object with a \"points\" array");
    }
    for (const auto& p : json["points"]) {
      if (!p.is_array() || p.size() != 3) {
        throw IoError(IoErrorKind::kParse, path.string(), "each point must be [x, y, z]");
      }
      const glm::vec3 point(p[0].get<float>(), p[1].get<float>(), p[2].get<float>());
      if (!std::isfinite(point.x) || !std::isfinite(point.y) || !std::isfinite(point.z)) {
        throw IoError(IoErrorKind::kNonFinite, path.string(), "a landmark point is not finite");
      }
      landmarks.points.push_back(point);
    }
    const std::size_t n = landmarks.points.size();
    if (n == 0) throw IoError(IoErrorKind::kEmpty, path.string(), "the landmark file has no points");
    if (json.contains("confidence")) {
      landmarks.confidence = json["confidence"].get<std::vector<float>>();
      for (float c : landmarks.confidence) {
        if (!(c >= 0.0f && c <= 1.0f)) {
          throw IoError(IoErrorKind::kParse, path.string(), "confidences must be in [0, 1]");
        }
      }
    } else {
      landmarks.confidence.assign(n, 1.0f);
    }
    if (json.contains("indices")) {
      landmarks.indices = json["indices"].get<std::vector<std::uint32_t>>();
    } else {
      for (std::uint32_t i = 0; i < n; ++i) landmarks.indices.push_back(i);
    }
    if (landmarks.confidence.size() != n || landmarks.indices.size() != n) {
      throw IoError(IoErrorKind::kParse, path.string(),
                    "\"points\", \"confidence\" and \"indices\" must have the same length");
    }
    for (std::uint32_t i : landmarks.indices) {
      if (i >= kDlibLandmarkCount) {
        throw IoError(IoErrorKind::kIndexOutOfRange, path.string(),
                      "landmark index " + std::to_string(i) + " is outside dlib's 0..67");
      }
    }
  } catch (const nlohmann::json::exception& e) {
    throw IoError(IoErrorKind::kParse, path.string(), std::string("malformed landmark file: ") + e.what());
  }
  return landmarks;
}

}  // namespace facerig
