// A perspective camera for the photo fit: the landmarks moved to where a
// scaled orthographic camera along the same axis would see them (given the
// current shape's depths and the camera's distance), so that the fit itself
// stays orthographic; and the view that projects like the photo's camera.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "facerig/offline/photo/fit.h"
#include "photo/fit/shape_system.h"

namespace facerig {

namespace {

glm::vec3 Forward(const ScaledOrthoCamera& camera) {
  return {camera.rotation[0][2], camera.rotation[1][2], camera.rotation[2][2]};
}

// A point nearer than this fraction of the distance is treated as this near
// (a guard against a distance shorter than the face is deep).
constexpr float kNearestFraction = 0.2f;

}  // namespace

std::vector<glm::vec2> OrthographicPixels(std::span<const glm::vec2> pixels, std::span<const glm::vec3> points,
                                          const ScaledOrthoCamera& camera, float distance, int width, int height) {
  std::vector<glm::vec2> moved(pixels.begin(), pixels.end());
  if (!(distance > 0.0f) || points.size() != pixels.size()) return moved;
  const glm::vec3 forward = Forward(camera);
  const glm::vec3 centre = photo_shape::Centroid(points);
  const glm::vec2 image_centre(0.5f * static_cast<float>(width), 0.5f * static_cast<float>(height));
  for (std::size_t k = 0; k < moved.size(); ++k) {
    // The point's distance from the camera along its axis, over the centroid's.
    const float depth = std::max(kNearestFraction * distance, distance - glm::dot(forward, points[k] - centre));
    moved[k] = image_centre + (pixels[k] - image_centre) * (depth / distance);
  }
  return moved;
}

RasterView ToPerspectiveView(const ScaledOrthoCamera& camera, int width, int height, glm::vec3 depth_centre,
                             float distance) {
  RasterView view = ToRasterView(camera, width, height, depth_centre);
  if (!(distance > 0.0f)) return view;
  // At depth_centre's depth the perspective view has the orthographic camera's scale.
  view.vertical_fov = 2.0f * std::atan(0.5f * static_cast<float>(height) / (camera.scale * distance));
  view.distance = distance;
  return view;
}

}  // namespace facerig
