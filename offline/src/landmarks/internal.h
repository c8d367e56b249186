// Internal pieces of the landmark detector (landmarks*.cpp), one topic per
// file: framing the face from the mesh alone (landmarks_frame.cpp), lifting
// the 2D landmarks of a close-up back to the surface (landmarks_lift.cpp),
// the detector itself, the only file that includes dlib (landmarks.cpp), and
// landmark files (landmarks_io.cpp).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/render/rasterizer.h"
#include "facerig/runtime/rig.h"

namespace facerig::landmarks_detail {

inline constexpr double kPi = 3.14159265358979323846;

// `v` rotated by `radians` about the unit `axis`.
glm::vec3 Rotate(glm::vec3 v, glm::vec3 axis, float radians);

// The mesh's own estimate of where its face is: centre, up and the normal of
// the mirror-symmetry plane (the left-right axis).
struct MeshFrame {
  glm::vec3 centre{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  glm::vec3 lateral{1.0f, 0.0f, 0.0f};
};

// A coarse stand-in for a large mesh (vertex clustering on a grid): the
// front-view estimate only needs the overall shape.
struct ProxyMesh {
  std::vector<glm::vec3> positions;
  std::vector<Triangle> triangles;
};

// What the front view is estimated on, and the estimate.
struct FramingMesh {
  // A clustered copy of a large mesh; for a smaller mesh with stray vertices,
  // only its used vertices; otherwise empty.
  ProxyMesh proxy;
  MeshFrame frame;

  // The points whole-mesh views are framed on (no stray vertices).
  std::span<const glm::vec3> FramedPositions(std::span<const glm::vec3> positions) const {
    return proxy.positions.empty() ? positions : std::span<const glm::vec3>(proxy.positions);
  }
};

// \throw InvalidInputError when every triangle of the mesh is degenerate.
FramingMesh PrepareFraming(const Mesh& mesh, std::size_t proxy_triangle_limit, int proxy_cells);

// Orthographic view of the face: `centre` in the middle, the face (size
// `face_size`, world units) filling half of the image.
RasterView FaceView(glm::vec3 forward, glm::vec3 up, glm::vec3 centre, float face_size, int size);

// Orthographic view looking at the face along -forward, up as given, framing
// all of `positions`.
RasterView FrontView(std::span<const glm::vec3> positions, glm::vec3 forward, glm::vec3 up, int size);

// Row `row` of the view's rotation: 0 right, 1 up, 2 forward (world coordinates).
glm::vec3 ViewAxis(const RasterView& view, int row);

float PixelsPerUnit(const RasterView& view);

// World point on the image plane through the centre, under pixel (x, y).
glm::vec3 Unproject(const RasterView& view, glm::vec2 pixel);

// The detected landmarks on the surface, with the pixels they were read from.
struct LiftedLandmarks {
  FaceLandmarks landmarks;
  std::vector<glm::vec2> pixels;  // calibrated, snapped
  int snapped = 0;
};

// dlib's 68 pixels in the close-up `view` (its render gave `buffers`; the face,
// `face_height` world units, fills half of it) to 3D points on `mesh`: the
// calibration offsets removed, a point that fell through a hole or onto a back
// face snapped to the nearest front surface pixel, then the viewing ray
// intersected with the plane of the triangle under it.
// \throw LandmarkDetectionError when a landmark has no surface near it.
LiftedLandmarks LiftLandmarks(const Mesh& mesh, const RasterView& view, const RasterBuffers& buffers,
                              float face_height, std::span<const glm::vec2> detected_pixels,
                              const LandmarkParams& params);

}  // namespace facerig::landmarks_detail
