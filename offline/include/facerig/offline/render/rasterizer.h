// A small deterministic CPU rasterizer for offline work: previews of rigs,
// renders for 2D landmark detectors, and the inverse z-buffer (pixel -> the
// triangle and barycentrics under it -> a 3D surface point) that automatic
// landmarking needs.
//
// Conventions: world positions in the mesh's units; the view maps world to
// camera space (x right, y up, the camera looks along -z, so larger z is
// nearer); images are row-major, row 0 at the top, pixel centres at +0.5.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "facerig/runtime/mesh.h"
#include "facerig/runtime/rig.h"

namespace facerig {

struct RasterView {
  // World -> camera rotation (rows are the camera axes in world coordinates).
  glm::mat3 rotation{1.0f};
  // World point that lands at the image centre.
  glm::vec3 centre{0.0f};
  // Orthographic: half the image height in world units. Perspective: unused.
  float half_extent = 1.0f;
  // > 0: perspective with this vertical field of view (radians), the camera at
  // `distance` from `centre` along +z of the camera frame. 0: orthographic.
  float vertical_fov = 0.0f;
  float distance = 0.0f;
  int width = 256;
  int height = 256;

  // A camera looking at `centre` from the front (+z of the world, +y up),
  // turned about the world +y axis by `yaw` radians (positive: the camera
  // moves towards +x), orthographic, framing +-half_extent vertically.
  static RasterView Orbit(glm::vec3 centre, float half_extent, int width, int height,
                          float yaw = 0.0f, float pitch = 0.0f);
  // A camera with the given orthonormal axes in world coordinates (`forward`
  // points towards the camera), looking at `centre`, orthographic, framing
  // +-half_extent vertically.
  static RasterView FromAxes(glm::vec3 right, glm::vec3 up, glm::vec3 forward, glm::vec3 centre, float half_extent,
                             int width, int height);
};

// Pixel (x right, y down, continuous) and camera depth of a world point.
glm::vec3 ProjectToImage(const RasterView& view, glm::vec3 world);

inline constexpr std::int32_t kNoTriangle = -1;

// The z-buffer: for each pixel the nearest triangle (kNoTriangle when empty),
// its barycentrics (weights of the triangle's vertices 0, 1, 2) at the pixel
// centre, camera depth, and whether that triangle faces away from the camera.
struct RasterBuffers {
  int width = 0;
  int height = 0;
  std::vector<std::int32_t> triangle_ids;
  std::vector<glm::vec3> barycentrics;
  std::vector<float> depths;
  std::vector<std::uint8_t> back_facing;

  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
  }
  // The 3D surface point under pixel (x, y), or false when the pixel is empty.
  bool SurfacePoint(int x, int y, const Mesh& mesh, glm::vec3& point) const;
};

// Rasterizes every triangle (both windings) with a depth test. Deterministic:
// ties keep the lower triangle id. Throws InvalidInputError on a bad view
// or a vertex index out of range.
RasterBuffers Rasterize(const Mesh& mesh, const RasterView& view);

struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // RGB, row-major, row 0 at the top
};

struct ShadeParams {
  glm::vec3 background{0.16f, 0.17f, 0.20f};
  // Direction towards the light in camera space: 30 degrees above the view axis.
  glm::vec3 light{0.0f, 0.5f, 0.8660254f};
  float ambient = 0.25f;
  // Colour of back faces (inside of open meshes): dark, so holes read as holes.
  glm::vec3 back_face{0.05f, 0.03f, 0.03f};
};

// Lambert shading of the z-buffer with the mesh's corner normals
// interpolated (face normals when it has none).
// triangle_albedo: one colour per triangle (see PartAlbedo), or empty for grey.
RgbImage Shade(const RasterBuffers& buffers, const Mesh& mesh,
               std::span<const glm::vec3> triangle_albedo, const RasterView& view,
               const ShadeParams& params = {});

// Per-triangle albedo from the rig's part names ("skin", "iris_L", "teeth_upper", ...);
// unknown parts are light grey.
std::vector<glm::vec3> PartAlbedo(const Rig& rig);

// Rasterize + Shade a posed rig (positions/normals as from a BlendJob).
RgbImage RenderRig(const Rig& rig, std::span<const glm::vec3> positions,
                   std::span<const glm::vec3> normals, const RasterView& view,
                   const ShadeParams& params = {});

// Luminance (Rec. 601), for 2D detectors.
std::vector<std::uint8_t> ToGray(const RgbImage& image);

// PNG through OpenCV; throws std::runtime_error when writing fails.
void WritePng(const std::filesystem::path& path, const RgbImage& image);

}  // namespace facerig
