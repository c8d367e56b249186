#include "facerig/offline/render/rasterizer.h"
#include "facerig/offline/error.h"
#include "facerig/offline/io/image_codec.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace facerig {

RasterView RasterView::Orbit(glm::vec3 centre, float half_extent, int width, int height, float yaw,
                             float pitch) {
  // Camera axes in world coordinates: the camera sits on +z turned by yaw
  // about +y, then tilted by pitch (positive: camera above, looking down).
  const glm::vec3 forward{std::sin(yaw) * std::cos(pitch), std::sin(pitch),
                          std::cos(yaw) * std::cos(pitch)};  // towards the camera
  const glm::vec3 right = glm::normalize(glm::cross(glm::vec3(0.0f, 1.0f, 0.0f), forward));
  const glm::vec3 up = glm::cross(forward, right);
  return FromAxes(right, up, forward, centre, half_extent, width, height);
}

RasterView RasterView::FromAxes(glm::vec3 right, glm::vec3 up, glm::vec3 forward, glm::vec3 centre,
                                float half_extent, int width, int height) {
  RasterView view;
  // glm is column-major: set the rows to the camera axes.
  for (int c = 0; c < 3; ++c) {
    view.rotation[c][0] = right[c];
    view.rotation[c][1] = up[c];
    view.rotation[c][2] = forward[c];
  }
  view.centre = centre;
  view.half_extent = half_extent;
  view.width = width;
  view.height = height;
  return view;
}

namespace {

void CheckView(const RasterView& view) {
  if (view.width <= 0 || view.height <= 0 || view.width > 16384 || view.height > 16384) {
    throw InvalidInputError("RasterView: image size must be in [1, 16384]");
  }
  if (view.vertical_fov > 0.0f) {
    if (!(view.vertical_fov < 3.1f) || !(view.distance > 0.0f)) {
      throw InvalidInputError("RasterView: perspective needs fov < pi and distance > 0");
    }
  } else if (!(view.half_extent > 0.0f)) {
    throw InvalidInputError("RasterView: half_extent must be > 0");
  }
}

}  // namespace

glm::vec3 ProjectToImage(const RasterView& view, glm::vec3 world) {
  const glm::vec3 cam = view.rotation * (world - view.centre);
  const float h = static_cast<float>(view.height);
  const float w = static_cast<float>(view.width);
  // Pixels per world unit at the centre plane.
  float scale = 0.5f * h / view.half_extent;
  float depth = cam.z;
  if (view.vertical_fov > 0.0f) {
    const float distance_to_camera = std::max(view.distance - cam.z, 1e-6f);
    scale = 0.5f * h / (std::tan(0.5f * view.vertical_fov) * distance_to_camera);
    depth = -distance_to_camera;  // nearer is larger, as in the orthographic case
  }
  return {0.5f * w + cam.x * scale, 0.5f * h - cam.y * scale, depth};
}

bool RasterBuffers::SurfacePoint(int x, int y, const Mesh& mesh, glm::vec3& point) const {
  if (x < 0 || y < 0 || x >= width || y >= height) return false;
  const std::int32_t id = triangle_ids[index(x, y)];
  if (id == kNoTriangle || static_cast<std::size_t>(id) >= mesh.triangles.size()) return false;
  const Triangle& t = mesh.triangles[static_cast<std::size_t>(id)];
  const glm::vec3 b = barycentrics[index(x, y)];
  point = b.x * mesh.positions[t[0]] + b.y * mesh.positions[t[1]] + b.z * mesh.positions[t[2]];
  return true;
}

namespace {

void CheckTriangles(const Mesh& mesh) {
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (std::uint32_t v : mesh.triangles[t]) {
      if (v >= mesh.positions.size()) {
        throw InvalidInputError("Rasterize: triangle " + std::to_string(t) + " uses vertex " + std::to_string(v) +
                                " >= " + std::to_string(mesh.positions.size()));
      }
    }
  }
}

RasterBuffers EmptyBuffers(const RasterView& view) {
  RasterBuffers buffers;
  buffers.width = view.width;
  buffers.height = view.height;
  const std::size_t pixel_count = static_cast<std::size_t>(view.width) * static_cast<std::size_t>(view.height);
  buffers.triangle_ids.assign(pixel_count, kNoTriangle);
  buffers.barycentrics.assign(pixel_count, glm::vec3(0.0f));
  buffers.depths.assign(pixel_count, -std::numeric_limits<float>::infinity());
  buffers.back_facing.assign(pixel_count, 0);
  return buffers;
}

// Draws triangle `t` (corners a, b, c in image coordinates, depth in z) into
// the buffers where it is nearer than what they hold.
void RasterizeTriangle(RasterBuffers& buffers, std::size_t t, const glm::vec3& a, const glm::vec3& b,
                       const glm::vec3& c) {
  const auto width = static_cast<float>(buffers.width), height = static_cast<float>(buffers.height);
  // Off-screen (most triangles of a close-up): skip before any other work.
  const float min_x = std::min({a.x, b.x, c.x}), max_x = std::max({a.x, b.x, c.x});
  const float min_y = std::min({a.y, b.y, c.y}), max_y = std::max({a.y, b.y, c.y});
  if (!(max_x >= 0.0f && max_y >= 0.0f && min_x < width && min_y < height)) return;
  // Signed area in image coordinates (y down): negative = counter-clockwise
  // on screen when seen from the camera = front facing.
  const double area = (static_cast<double>(b.x) - a.x) * (static_cast<double>(c.y) - a.y) -
                      (static_cast<double>(c.x) - a.x) * (static_cast<double>(b.y) - a.y);
  if (!(std::abs(area) >= 1e-12)) return;  // degenerate on screen, or non-finite
  const double inverse_area = 1.0 / area;
  const std::uint8_t back = area > 0.0 ? 1 : 0;
  // Only pixels whose centres lie in the bounding box can be covered: a
  // pixel-sized triangle tests one to four pixels, not nine.
  const int x0 = std::max(0, static_cast<int>(std::ceil(min_x - 0.5f)));
  const int x1 = std::min(buffers.width - 1, static_cast<int>(std::floor(max_x - 0.5f)));
  const int y0 = std::max(0, static_cast<int>(std::ceil(min_y - 0.5f)));
  const int y1 = std::min(buffers.height - 1, static_cast<int>(std::floor(max_y - 0.5f)));
  for (int y = y0; y <= y1; ++y) {
    const double py = y + 0.5;
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5;
      // Barycentrics from edge functions, in double so the coverage test is
      // exact enough that shared edges leave no cracks.
      const double w0 = ((static_cast<double>(b.x) - px) * (static_cast<double>(c.y) - py) -
                         (static_cast<double>(c.x) - px) * (static_cast<double>(b.y) - py)) * inverse_area;
      if (w0 < 0.0) continue;
      const double w1 = ((static_cast<double>(c.x) - px) * (static_cast<double>(a.y) - py) -
                         (static_cast<double>(a.x) - px) * (static_cast<double>(c.y) - py)) * inverse_area;
      const double w2 = 1.0 - w0 - w1;
      if (w1 < 0.0 || w2 < 0.0) continue;
      const float depth = static_cast<float>(w0 * a.z + w1 * b.z + w2 * c.z);
      const std::size_t i = buffers.index(x, y);
      if (depth > buffers.depths[i]) {
        buffers.depths[i] = depth;
        buffers.triangle_ids[i] = static_cast<std::int32_t>(t);
        buffers.barycentrics[i] =
            glm::vec3(static_cast<float>(w0), static_cast<float>(w1), static_cast<float>(w2));
        buffers.back_facing[i] = back;
      }
    }
  }
}

}  // namespace

RasterBuffers Rasterize(const Mesh& mesh, const RasterView& view) {
  CheckView(view);
  CheckTriangles(mesh);
  RasterBuffers buffers = EmptyBuffers(view);
  std::vector<glm::vec3> projected(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) projected[v] = ProjectToImage(view, mesh.positions[v]);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    RasterizeTriangle(buffers, t, projected[tri[0]], projected[tri[1]], projected[tri[2]]);
  }
  return buffers;
}

RgbImage Shade(const RasterBuffers& buffers, const Mesh& mesh, std::span<const glm::vec3> triangle_albedo,
               const RasterView& view, const ShadeParams& params) {
  const std::span<const glm::vec3> positions = mesh.positions;
  const std::span<const glm::vec3> normals = mesh.corner_normals;
  const std::span<const Triangle> triangles = mesh.triangles;
  RgbImage image;
  image.width = buffers.width;
  image.height = buffers.height;
  image.pixels.resize(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3);
  const glm::vec3 light = glm::normalize(params.light);
  auto to_byte = [](float v) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
  };
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::size_t i = buffers.index(x, y);
      glm::vec3 colour = params.background;
      const std::int32_t id = buffers.triangle_ids[i];
      if (id != kNoTriangle) {
        const Triangle& t = triangles[static_cast<std::size_t>(id)];
        if (buffers.back_facing[i]) {
          colour = params.back_face;
        } else {
          const glm::vec3 b = buffers.barycentrics[i];
          glm::vec3 n;
          if (normals.size() == 3 * triangles.size()) {
            const std::size_t corner = 3 * static_cast<std::size_t>(id);
            n = b.x * normals[corner] + b.y * normals[corner + 1] + b.z * normals[corner + 2];
          } else {
            n = glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
          }
          const float length = glm::length(n);
          n = length > 0.0f ? view.rotation * (n / length) : glm::vec3(0.0f, 0.0f, 1.0f);
          const float diffuse = std::max(0.0f, glm::dot(n, light));
          const glm::vec3 albedo = triangle_albedo.size() == triangles.size()
                                       ? triangle_albedo[static_cast<std::size_t>(id)]
                                       : glm::vec3(0.8f);
          colour = albedo * (params.ambient + (1.0f - params.ambient) * diffuse);
        }
      }
      image.pixels[3 * i + 0] = to_byte(colour.r);
      image.pixels[3 * i + 1] = to_byte(colour.g);
      image.pixels[3 * i + 2] = to_byte(colour.b);
    }
  }
  return image;
}

std::vector<glm::vec3> PartAlbedo(const Rig& rig) {
  std::vector<glm::vec3> albedo(rig.triangle_count(), glm::vec3(0.8f));
  for (const Part& part : rig.parts()) {
    glm::vec3 colour{0.8f};
    const std::string& name = part.name;
    if (name == "skin") colour = {0.87f, 0.69f, 0.58f};
    else if (name.rfind("eye_white", 0) == 0) colour = {0.95f, 0.94f, 0.92f};
    else if (name.rfind("iris", 0) == 0) colour = {0.25f, 0.42f, 0.55f};
    else if (name.rfind("pupil", 0) == 0) colour = {0.03f, 0.03f, 0.03f};
    else if (name.rfind("teeth", 0) == 0) colour = {0.93f, 0.91f, 0.84f};
    else if (name == "mouth_inner") colour = {0.35f, 0.10f, 0.10f};
    else if (name == "tongue") colour = {0.75f, 0.35f, 0.35f};
    const std::uint32_t end = std::min<std::uint32_t>(part.first_triangle + part.triangle_count,
                                                      static_cast<std::uint32_t>(albedo.size()));
    for (std::uint32_t t = part.first_triangle; t < end; ++t) albedo[t] = colour;
  }
  return albedo;
}

RgbImage RenderRig(const Rig& rig, std::span<const glm::vec3> positions,
                   std::span<const glm::vec3> normals, const RasterView& view,
                   const ShadeParams& params) {
  Mesh posed{.positions = {positions.begin(), positions.end()}, .triangles = {rig.triangles().begin(), rig.triangles().end()}};
  if (normals.size() == positions.size()) {
    for (const Triangle& t : posed.triangles) {
      for (std::uint32_t v : t) posed.corner_normals.push_back(normals[v]);
    }
  }
  const RasterBuffers buffers = Rasterize(posed, view);
  const std::vector<glm::vec3> albedo = PartAlbedo(rig);
  return Shade(buffers, posed, albedo, view, params);
}

std::vector<std::uint8_t> ToGray(const RgbImage& image) {
  std::vector<std::uint8_t> gray(image.pixels.size() / 3);
  for (std::size_t i = 0; i < gray.size(); ++i) {
    const float luma = 0.299f * image.pixels[3 * i] + 0.587f * image.pixels[3 * i + 1] +
                       0.114f * image.pixels[3 * i + 2];
    gray[i] = static_cast<std::uint8_t>(std::lround(std::min(luma, 255.0f)));
  }
  return gray;
}

void WritePng(const std::filesystem::path& path, const RgbImage& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3) {
    throw std::runtime_error("WritePng: empty or inconsistent image for " + path.string());
  }
  cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.pixels.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  // Highest zlib effort: previews are committed, so smaller is better.
  const std::vector<std::uint8_t> png = EncodePngBytes(bgr, 9);
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  file.close();
  if (!file) throw std::runtime_error("WritePng: cannot write " + path.string());
}

}  // namespace facerig
