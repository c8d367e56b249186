// The photo's camera: a scaled orthographic camera fitted to 2D-3D pairs,
// its projection, and the perspective view that matches it at a distance.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/offline/render/rasterizer.h"

namespace facerig {

// Scaled orthographic camera: pixel = (w/2 + s r0.x + tx, h/2 - (s r1.x + ty)).
struct ScaledOrthoCamera {
  glm::mat3 rotation{1.0f};  // rows: camera right, up, towards the viewer (world coordinates)
  float scale = 1.0f;  // pixels per model unit
  glm::vec2 translation{0.0f};  // pixels, y up, from the image centre
};

// The least-squares affine camera from 2D-3D pairs, then the nearest scaled
// rotation (SVD) and its translation. \pre points.size() == pixels.size() >= 4.
// \throw InvalidInputError on mismatched sizes, too few points or a degenerate configuration.
ScaledOrthoCamera FitScaledOrthoCamera(std::span<const glm::vec3> points, std::span<const glm::vec2> pixels,
                                       std::span<const float> weights, int width, int height);

glm::vec2 ProjectPixel(const ScaledOrthoCamera& camera, glm::vec3 point, int width, int height);

// The same camera as a RasterView of a width x height image: Rasterize(mesh,
// view) overlays the mesh on the photo. `depth_centre`: a point of the model
// (its depth sets the view's centre along the viewing axis).
RasterView ToRasterView(const ScaledOrthoCamera& camera, int width, int height, glm::vec3 depth_centre);


// Where a scaled orthographic camera along `camera`'s axis would see each of
// `points` that a perspective camera `distance` (model units) from their
// centroid shows at `pixels`: each pixel moved from the image centre (the
// principal point) by its point's depth over the centroid's. `distance` <= 0
// or mismatched sizes: the pixels unchanged.
std::vector<glm::vec2> OrthographicPixels(std::span<const glm::vec2> pixels, std::span<const glm::vec3> points,
                                          const ScaledOrthoCamera& camera, float distance, int width, int height);

// The perspective view `distance` from `depth_centre` (on the camera's axis
// through the image centre) with the camera's rotation and, at depth_centre's
// depth, its scale: it projects as the photo's camera when the fit used
// OrthographicPixels. `distance` <= 0: ToRasterView.
RasterView ToPerspectiveView(const ScaledOrthoCamera& camera, int width, int height, glm::vec3 depth_centre,
                             float distance);

}  // namespace facerig
