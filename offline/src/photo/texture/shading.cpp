// The photo's light on the skin by how the surface tilts: what the photo does
// not show (the neck under the chin, the sides) takes the skin colour shaded
// as the photo shades the skin it does show at that tilt, so the fill meets
// the face without a lighter band.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "facerig/offline/geometry/stats.h"
#include "photo/texture/internal.h"

namespace facerig::photo_texture {
namespace {

int BinOf(float tilt) {
  const float at = 0.5f * (std::clamp(tilt, -1.0f, 1.0f) + 1.0f) * static_cast<float>(SkinShading::kBins);
  return std::min(static_cast<int>(at), SkinShading::kBins - 1);
}

// A gain the photo's light can plausibly give: beyond it, a bin holds
// something else (brows, nostrils, a beard's shadow).
constexpr float kLeastGain = 0.6f, kMostGain = 1.1f;

}  // namespace

float SkinShading::At(float tilt) const {
  const float at = 0.5f * (std::clamp(tilt, -1.0f, 1.0f) + 1.0f) * static_cast<float>(kBins) - 0.5f;
  if (at <= 0.0f) return gain.front();
  if (at >= static_cast<float>(kBins - 1)) return gain.back();
  const int low = static_cast<int>(at);
  const float t = at - static_cast<float>(low);
  return (1.0f - t) * gain[static_cast<std::size_t>(low)] + t * gain[static_cast<std::size_t>(low + 1)];
}

SkinShading EstimateSkinShading(const TexelLayers& layers, const glm::vec3& skin_colour) {
  SkinShading shading;
  const float reference = Luma(skin_colour);
  if (!(reference > 0.0f)) return shading;
  std::array<std::vector<float>, SkinShading::kBins> ratios;
  for (std::size_t i = 0; i < layers.skin.size(); ++i) {
    if (!layers.skin[i] || layers.direct_weight[i] < 0.5f || layers.scalp[i] > 0.0f) continue;
    ratios[static_cast<std::size_t>(BinOf(layers.tilt[i]))].push_back(Luma(layers.direct_colour[i]) / reference);
  }
  // Bins the photo shows too little of take their nearest shown neighbour's gain.
  constexpr std::size_t kLeast = 256;
  std::array<bool, SkinShading::kBins> shown{};
  for (std::size_t b = 0; b < ratios.size(); ++b) {
    shown[b] = ratios[b].size() >= kLeast;
    if (shown[b]) shading.gain[b] = std::clamp(Median(std::move(ratios[b])), kLeastGain, kMostGain);
  }
  for (int b = 0; b < SkinShading::kBins; ++b) {
    if (shown[static_cast<std::size_t>(b)]) continue;
    for (int d = 1; d < SkinShading::kBins; ++d) {
      const int below = b - d, above = b + d;
      if (below >= 0 && shown[static_cast<std::size_t>(below)]) { shading.gain[static_cast<std::size_t>(b)] = shading.gain[static_cast<std::size_t>(below)]; break; }
      if (above < SkinShading::kBins && shown[static_cast<std::size_t>(above)]) { shading.gain[static_cast<std::size_t>(b)] = shading.gain[static_cast<std::size_t>(above)]; break; }
    }
  }
  return shading;
}

}  // namespace facerig::photo_texture
