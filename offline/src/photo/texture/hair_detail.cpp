// The template's own painted hair (the built-in head's strands and clumps)
// kept as detail on the scalp's hair colour.
#include <algorithm>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "facerig/offline/default_head/default_head.h"
#include "photo/texture/internal.h"

namespace facerig::photo_texture {
namespace {

// The image the baked skin triangles wear (-1: none).
std::int32_t SkinImage(const Mesh& mesh, const std::vector<std::uint8_t>& baked) {
  if (mesh.triangle_materials.empty()) return -1;
  for (std::size_t t = 0; t < baked.size(); ++t) {
    if (!baked[t]) continue;
    const std::int32_t image = mesh.materials[mesh.triangle_materials[t]].base_colour_image;
    if (image >= 0) return image;
  }
  return -1;
}

}  // namespace

void AddPaintedHairDetail(const Mesh& mesh, const std::vector<std::uint8_t>& baked, TexelLayers& layers) {
  const std::int32_t index = SkinImage(mesh, baked);
  if (index < 0) return;
  RgbImage painted;
  try {
    painted = DecodeImage(mesh.images[static_cast<std::size_t>(index)]);
  } catch (const std::runtime_error&) {
    return;  // a texture that does not decode adds no detail
  }
  if (painted.width <= 0 || painted.height <= 0) return;
  const cv::Mat rgb(painted.height, painted.width, CV_8UC3, painted.pixels.data());
  cv::Mat luma;
  cv::cvtColor(rgb, luma, cv::COLOR_RGB2GRAY);
  luma.convertTo(luma, CV_32F, 1.0 / 255.0);
  if (luma.cols != layers.size || luma.rows != layers.size) {
    cv::resize(luma, luma, cv::Size(layers.size, layers.size), 0.0, 0.0, cv::INTER_AREA);
  }
  // Detail only: the painted light over its local mean, so the painting's own
  // hairline and colour do not come along.
  cv::Mat local;
  cv::GaussianBlur(luma, local, cv::Size(0, 0), std::max(2.0, layers.size / 128.0));
  for (int y = 0; y < layers.size; ++y) {
    for (int x = 0; x < layers.size; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(layers.size) + static_cast<std::size_t>(x);
      if (!layers.skin[i] || layers.scalp[i] <= 0.0f) continue;
      const float ratio = std::clamp(luma.at<float>(y, x) / std::max(local.at<float>(y, x), 0.02f), 0.7f, 1.35f);
      layers.hair_colour[i] = glm::min(layers.hair_colour[i] * ratio, glm::vec3(1.0f));
    }
  }
}

}  // namespace facerig::photo_texture
