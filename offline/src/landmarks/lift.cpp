// 2D landmarks of the close-up back to 3D through its z-buffer (triangle id
// and barycentrics per pixel).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "facerig/offline/error.h"
#include "landmarks/internal.h"

namespace facerig::landmarks_detail {
namespace {

// dlib's 68 points minus the ICT-FaceKit landmark vertices, in the close-up
// view (x right, y down), as fractions of the detected face box: subtracted
// from each detection when LandmarkParams::calibrate. Measured on 12 random
// ICT faces (seeds 101-112, re-meshed, rotated; the tests use other seeds).
constexpr std::array<std::array<float, 2>, kDlibLandmarkCount> kCalibration{{
#include "landmarks/calibration.inc"
}};

// The close-up's z-buffer read as surface: a pixel is usable when it shows a
// front face; larger depth is nearer the viewer.
class FrontSurface {
 public:
  FrontSurface(const RasterBuffers& buffers, int width, int height)
      : buffers_(buffers), width_(width), height_(height) {}

  bool Usable(int x, int y) const {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return false;
    const std::size_t i = buffers_.index(x, y);
    return buffers_.triangle_ids[i] != kNoTriangle && !buffers_.back_facing[i];
  }

  float Depth(int x, int y) const { return buffers_.depths[buffers_.index(x, y)]; }

  // The nearest front surface around a pixel (-infinity when there is none).
  float FrontDepth(int x0, int y0, int radius) const {
    float front = -std::numeric_limits<float>::infinity();
    for (int y = y0 - radius; y <= y0 + radius; ++y) {
      for (int x = x0 - radius; x <= x0 + radius; ++x) {
        if (Usable(x, y)) front = std::max(front, Depth(x, y));
      }
    }
    return front;
  }

 private:
  const RasterBuffers& buffers_;
  int width_;
  int height_;
};

// Ring search outwards from `start` for the nearest usable pixel no more than
// `hole_depth` behind `front` (any usable pixel when `front` is not finite).
std::optional<glm::ivec2> NearestFrontPixel(const FrontSurface& surface, glm::ivec2 start, float front,
                                            float hole_depth, int max_radius) {
  std::optional<glm::ivec2> found;
  float found_d2 = std::numeric_limits<float>::infinity();
  for (int r = 1; r <= max_radius && !found; ++r) {
    for (int y = start.y - r; y <= start.y + r; ++y) {
      for (int x = start.x - r; x <= start.x + r; ++x) {
        if (std::max(std::abs(x - start.x), std::abs(y - start.y)) != r || !surface.Usable(x, y)) continue;
        if (std::isfinite(front) && surface.Depth(x, y) < front - hole_depth) continue;
        const float d2 = static_cast<float>((x - start.x) * (x - start.x) + (y - start.y) * (y - start.y));
        if (d2 < found_d2) {
          found_d2 = d2;
          found = glm::ivec2(x, y);
        }
      }
    }
  }
  return found;
}

// The surface point under `pixel` (inside buffer pixel `at`): the barycentric
// point of the triangle there, or, sub-pixel, where the viewing ray meets the
// triangle's plane, unless the plane is too oblique to the view for that to
// stay within the pixel.
glm::vec3 SurfacePointUnder(const Mesh& mesh, const RasterView& view, const RasterBuffers& buffers, glm::ivec2 at,
                            glm::vec2 pixel) {
  const std::span<const glm::vec3> positions = mesh.positions;
  const std::size_t i = buffers.index(at.x, at.y);
  const Triangle& t = mesh.triangles[static_cast<std::size_t>(buffers.triangle_ids[i])];
  const glm::vec3 b = buffers.barycentrics[i];
  glm::vec3 point = b.x * positions[t[0]] + b.y * positions[t[1]] + b.z * positions[t[2]];
  const glm::vec3 normal = glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
  const glm::vec3 origin = Unproject(view, pixel);
  const glm::vec3 view_forward = ViewAxis(view, 2);
  const float denominator = glm::dot(normal, view_forward);
  if (std::abs(denominator) > 0.2f * glm::length(normal)) {
    const float along = glm::dot(normal, point - origin) / denominator;
    const glm::vec3 on_plane = origin + along * view_forward;
    if (glm::length(on_plane - point) < 1.5f / PixelsPerUnit(view)) point = on_plane;
  }
  return point;
}

}  // namespace

LiftedLandmarks LiftLandmarks(const Mesh& mesh, const RasterView& view, const RasterBuffers& buffers,
                              float face_height, std::span<const glm::vec2> detected_pixels,
                              const LandmarkParams& params) {
  const FrontSurface surface(buffers, view.width, view.height);
  const float hole_depth = params.hole_depth_fraction * face_height;
  const int window = std::max(2, static_cast<int>(0.03f * face_height * PixelsPerUnit(view)));
  const int max_radius = std::max(view.width, view.height) / 4;
  LiftedLandmarks lifted;
  lifted.landmarks.points.resize(kDlibLandmarkCount);
  lifted.landmarks.confidence.resize(kDlibLandmarkCount);
  lifted.landmarks.indices.resize(kDlibLandmarkCount);
  lifted.pixels.resize(kDlibLandmarkCount);
  for (std::size_t k = 0; k < kDlibLandmarkCount; ++k) {
    glm::vec2 pixel = detected_pixels[k];
    if (params.calibrate) {
      const float box = 0.5f * static_cast<float>(params.landmark_image_size);
      pixel -= box * glm::vec2(kCalibration[k][0], kCalibration[k][1]);
    }
    glm::ivec2 at(static_cast<int>(std::floor(pixel.x)), static_cast<int>(std::floor(pixel.y)));
    const float front = surface.FrontDepth(at.x, at.y, window);
    const bool good = surface.Usable(at.x, at.y) && surface.Depth(at.x, at.y) >= front - hole_depth;
    float confidence = k < 17 ? params.jaw_confidence : 1.0f;
    if (!good) {
      // Fell through a hole or onto a back face: the nearest pixel on the front surface.
      const std::optional<glm::ivec2> snapped = NearestFrontPixel(surface, at, front, hole_depth, max_radius);
      if (!snapped) {
        throw LandmarkDetectionError("landmarks: landmark " + std::to_string(k) +
                                     " has no surface near it; give the landmarks in a file (--landmarks)");
      }
      at = *snapped;
      pixel = {static_cast<float>(at.x) + 0.5f, static_cast<float>(at.y) + 0.5f};
      confidence *= params.snapped_confidence_factor;
      ++lifted.snapped;
    }
    lifted.landmarks.points[k] = SurfacePointUnder(mesh, view, buffers, at, pixel);
    lifted.landmarks.confidence[k] = confidence;
    lifted.landmarks.indices[k] = static_cast<std::uint32_t>(k);
    lifted.pixels[k] = pixel;
  }
  return lifted;
}

}  // namespace facerig::landmarks_detail
