// Previews of the default head: the offline rasterizer's Lambert shading
// times the albedo its materials give (the painted textures sampled at the
// interpolated UVs, or the base colour), so the pictures show what a
// textured renderer would.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>

#include "facerig/offline/default_head/default_head.h"
#include "facerig/offline/render/rasterizer.h"
#include "facerig/runtime/blend_job.h"
#include "facerig/runtime/shape_names.h"
#include "render/srgb.h"

namespace facerig {
namespace {

// Bilinear, clamped to the edge; sRGB 0..1.
glm::vec3 Sample(const RgbImage& image, glm::vec2 uv) {
  const float x = std::clamp(uv.x * static_cast<float>(image.width) - 0.5f, 0.0f, static_cast<float>(image.width - 1));
  // The rig's v goes up; image rows go down.
  const float y =
      std::clamp((1.0f - uv.y) * static_cast<float>(image.height) - 0.5f, 0.0f, static_cast<float>(image.height - 1));
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, image.width - 1), y1 = std::min(y0 + 1, image.height - 1);
  auto at = [&](int px, int py) {
    const std::size_t i = (static_cast<std::size_t>(py) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(px)) * 3;
    return glm::vec3(image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]) / 255.0f;
  };
  const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
  return (at(x0, y0) * (1.0f - fx) + at(x1, y0) * fx) * (1.0f - fy) + (at(x0, y1) * (1.0f - fx) + at(x1, y1) * fx) * fy;
}

// The rig's shading (white albedo) times each pixel's material colour.
class TexturedPreview {
 public:
  explicit TexturedPreview(const Rig& rig) : rig_(rig), triangle_material_(rig.triangles().size(), -1) {
    for (const EncodedImage& image : rig.images()) images_.push_back(DecodeImage(image));
    for (const Part& part : rig.parts()) {
      std::fill_n(triangle_material_.begin() + part.first_triangle, part.triangle_count, part.material);
    }
  }

  RgbImage Render(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals, const RasterView& view) const {
    Mesh posed{.positions = {positions.begin(), positions.end()}, .triangles = {rig_.triangles().begin(), rig_.triangles().end()}};
    for (const Triangle& t : posed.triangles) {
      for (std::uint32_t v : t) posed.corner_normals.push_back(normals[v]);
    }
    const RasterBuffers buffers = Rasterize(posed, view);
    const std::vector<glm::vec3> white(posed.triangles.size(), glm::vec3(1.0f));
    RgbImage image = Shade(buffers, posed, white, view);
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        const std::size_t i = buffers.index(x, y);
        const std::int32_t id = buffers.triangle_ids[i];
        if (id == kNoTriangle || buffers.back_facing[i]) continue;
        const glm::vec3 albedo = Albedo(static_cast<std::size_t>(id), buffers.barycentrics[i]);
        for (int c = 0; c < 3; ++c) {
          const float lit = image.pixels[3 * i + c] * albedo[c];
          image.pixels[3 * i + c] = static_cast<std::uint8_t>(std::lround(std::clamp(lit, 0.0f, 255.0f)));
        }
      }
    }
    return image;
  }

 private:
  glm::vec3 Albedo(std::size_t triangle, const glm::vec3& barycentric) const {
    const std::int32_t m = triangle_material_[triangle];
    if (m < 0) return glm::vec3(0.8f);
    const Material& material = rig_.materials()[static_cast<std::size_t>(m)];
    const glm::vec3 factor{LinearToSrgb(material.base_colour.r), LinearToSrgb(material.base_colour.g), LinearToSrgb(material.base_colour.b)};
    if (material.base_colour_image < 0 || rig_.uvs().empty()) return factor;
    const Triangle& t = rig_.triangles()[triangle];
    const glm::vec2 uv = barycentric.x * rig_.uvs()[t[0]] + barycentric.y * rig_.uvs()[t[1]] + barycentric.z * rig_.uvs()[t[2]];
    return factor * Sample(images_[static_cast<std::size_t>(material.base_colour_image)], uv);
  }

  const Rig& rig_;
  std::vector<RgbImage> images_;
  std::vector<std::int32_t> triangle_material_;
};

}  // namespace

std::vector<std::filesystem::path> WriteDefaultHeadPreviews(const Rig& rig,
                                                            const std::filesystem::path& directory,
                                                            int size) {
  struct Pose {
    const char* name;
    std::vector<std::pair<const char*, float>> weights;
  };
  const std::vector<Pose> poses = {
      {"neutral", {}},
      {"jaw_open", {{"jawOpen", 1.0f}}},
      {"smile", {{"mouthSmile_L", 1.0f}, {"mouthSmile_R", 1.0f}, {"eyeSquint_L", 0.4f}, {"eyeSquint_R", 0.4f}}},
      {"blink", {{"eyeBlink_L", 1.0f}, {"eyeBlink_R", 1.0f}}},
      {"speech", {{"jawOpen", 0.4f}, {"mouthFunnel", 0.3f}}},
      {"oh", {{"jawOpen", 0.35f}, {"mouthFunnel", 0.9f}}},
      {"ee", {{"jawOpen", 0.12f}, {"mouthStretch_L", 0.6f}, {"mouthStretch_R", 0.6f}, {"mouthSmile_L", 0.3f}, {"mouthSmile_R", 0.3f}}},
  };
  std::filesystem::create_directories(directory);
  std::vector<std::filesystem::path> written;
  std::vector<float> weights(rig.shape_count());
  std::vector<glm::vec3> positions(rig.vertex_count()), normals(rig.vertex_count());
  const glm::vec3 centre{0.0f, -1.5f, 0.0f};
  const TexturedPreview textured(rig);
  for (const Pose& pose : poses) {
    std::fill(weights.begin(), weights.end(), 0.0f);
    for (const auto& [name, weight] : pose.weights) {
      for (std::size_t index : FindShapesByArkitName(rig, name)) weights[index] = weight;
    }
    BlendJob job{&rig, weights, NormalMode::kRecompute, positions, normals};
    if (job.Run() != BlendJobError::kNone) throw std::logic_error("preview: blend failed");
    for (const auto& [view_name, yaw] : {std::pair<const char*, float>{"front", 0.0f},
                                         std::pair<const char*, float>{"three_quarter", 0.6f}}) {
      const RasterView view = RasterView::Orbit(centre, 13.5f, size, size, yaw);
      const std::filesystem::path path = directory / (std::string(pose.name) + "_" + view_name + ".png");
      WritePng(path, textured.Render(positions, normals, view));
      written.push_back(path);
    }
    if (pose.weights.empty()) {  // the whole head and neck in profile
      const RasterView view = RasterView::Orbit({0.0f, -3.5f, 0.0f}, 15.0f, size, size, 1.5708f);
      const std::filesystem::path path = directory / (std::string(pose.name) + "_profile.png");
      WritePng(path, textured.Render(positions, normals, view));
      written.push_back(path);
    }
  }
  // The painted textures as they are embedded, to look at on their own.
  for (const EncodedImage& image : rig.images()) {
    const std::filesystem::path path = directory / image.name;
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(image.bytes.data()), static_cast<std::streamsize>(image.bytes.size()));
    if (!out) throw std::runtime_error("preview: writing " + path.string() + " failed");
    written.push_back(path);
  }
  return written;
}

}  // namespace facerig
