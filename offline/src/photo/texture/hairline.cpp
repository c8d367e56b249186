// The hairline where the photo shows it: on the skin vertices the photo sees
// above the brows, the height (azimuth by azimuth) that best splits the
// forehead's skin below from the hair above.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "facerig/offline/photo/skin_mask.h"
#include "facerig/offline/geometry/stats.h"
#include "photo/texture/internal.h"

namespace facerig::photo_texture {
namespace {

// Per shift bin: each seen vertex's height relative to the rule's hairline,
// and whether the photo shows hair there.
struct Sample {
  float relative_height = 0.0f;
  bool hair = false;
};
using Bins = std::array<std::vector<Sample>, ScalpRegion::kShiftBins>;

glm::vec3 PixelColour(const RgbImage& photo, int x, int y) {
  const std::uint8_t* c = &photo.pixels[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(photo.width) + static_cast<std::size_t>(x))];
  return glm::vec3(c[0], c[1], c[2]) * (1.0f / 255.0f);
}

// The relative height splitting the bin's samples into skin below and hair
// above with the fewest exceptions; false when the photo shows no clear
// boundary (too few samples of either, or too many exceptions).
bool BestSplit(std::vector<Sample> samples, float& split) {
  constexpr std::size_t kLeast = 4;
  std::sort(samples.begin(), samples.end(), [](const Sample& a, const Sample& b) { return a.relative_height < b.relative_height; });
  std::size_t hair_total = 0;
  for (const Sample& s : samples) hair_total += s.hair ? 1 : 0;
  if (hair_total < kLeast || samples.size() - hair_total < kLeast) return false;
  // Splitting before sample i: hair below it and skin from it up are the exceptions.
  std::size_t hair_below = 0, best_errors = samples.size() + 1, best = 0;
  for (std::size_t i = 0; i <= samples.size(); ++i) {
    const std::size_t skin_above = (samples.size() - i) - (hair_total - hair_below);
    if (hair_below + skin_above < best_errors) best_errors = hair_below + skin_above, best = i;
    if (i < samples.size() && samples[i].hair) ++hair_below;
  }
  if (best == 0 || best == samples.size() || 5 * best_errors > samples.size()) return false;
  split = 0.5f * (samples[best - 1].relative_height + samples[best].relative_height);
  return true;
}

// Unmeasured bins take their nearest measured neighbour's shift, fading over
// three bins; then a [1 2 1] smoothing, so the line does not step.
void Spread(const std::array<bool, ScalpRegion::kShiftBins>& measured, std::array<float, ScalpRegion::kShiftBins>& shift) {
  constexpr int n = ScalpRegion::kShiftBins;
  std::array<float, n> filled{};
  for (int b = 0; b < n; ++b) {
    int nearest = -1;
    for (int other = 0; other < n; ++other) {
      if (measured[static_cast<std::size_t>(other)] && (nearest < 0 || std::abs(other - b) < std::abs(nearest - b))) nearest = other;
    }
    if (nearest < 0) return;
    const float fade = std::max(0.0f, 1.0f - static_cast<float>(std::abs(nearest - b)) / 3.0f);
    filled[static_cast<std::size_t>(b)] = fade * shift[static_cast<std::size_t>(nearest)];
  }
  for (int b = 0; b < n; ++b) {
    const float left = filled[static_cast<std::size_t>(std::max(b - 1, 0))], right = filled[static_cast<std::size_t>(std::min(b + 1, n - 1))];
    shift[static_cast<std::size_t>(b)] = 0.25f * left + 0.5f * filled[static_cast<std::size_t>(b)] + 0.25f * right;
  }
}

}  // namespace

bool PhotoSkinMedian(const RgbImage& photo, const PhotoSkinMask& skin, glm::vec3& colour) {
  if (skin.empty()) return false;
  std::array<std::vector<float>, 3> channels;
  for (int y = std::max(0, skin.top); y < std::min(photo.height, skin.top + skin.height); ++y) {
    for (int x = std::max(0, skin.left); x < std::min(photo.width, skin.left + skin.width); ++x) {
      if (skin.At(x, y) < 0.95f) continue;
      const glm::vec3 c = PixelColour(photo, x, y);
      for (int k = 0; k < 3; ++k) channels[static_cast<std::size_t>(k)].push_back(c[k]);
    }
  }
  if (channels[0].size() < 64) return false;
  for (int k = 0; k < 3; ++k) colour[k] = Median(std::move(channels[static_cast<std::size_t>(k)]));
  return true;
}

bool HairSource::IsHairAt(const glm::vec3& p, const glm::vec3& photo_colour, float reach) const {
  if (!scalp.found || skin_colour.x < 0.0f) return false;
  if (scalp.Height(p) < scalp.Hairline(scalp.Azimuth(p)) - reach) return false;
  return glm::length(photo_colour - colour) < glm::length(photo_colour - skin_colour);
}

int FitHairlineToPhoto(const Mesh& mesh, const std::vector<std::uint8_t>& skin_vertex, const RasterView& camera,
                       const RgbImage& photo, const PhotoSkinMask& skin, HairSource& hair) {
  ScalpRegion& scalp = hair.scalp;
  if (!scalp.found || hair.head == nullptr || hair.head->empty() || hair.skin_colour.x < 0.0f) return 0;
  const glm::vec3 towards_camera(camera.rotation[0][2], camera.rotation[1][2], camera.rotation[2][2]);
  // The head's centre at eye height: the scalp's azimuths turn about it.
  const glm::vec3 centre = scalp.eyes - 1.3f * scalp.spacing * scalp.forward;
  Bins bins;
  for (std::size_t v = 0; v < skin_vertex.size(); ++v) {
    const glm::vec3& p = mesh.positions[v];
    const float azimuth = scalp.Azimuth(p), height = scalp.Height(p);
    const int bin = static_cast<int>(std::lround((azimuth + ScalpRegion::kShiftReach) / ScalpRegion::kShiftBinDegrees));
    // Above the brows, round the front, facing the camera.
    if (!skin_vertex[v] || height < 0.3f || bin < 0 || bin >= ScalpRegion::kShiftBins) continue;
    if (glm::dot(glm::normalize(p - centre), towards_camera) < 0.5f) continue;
    const glm::vec3 q = ProjectToImage(camera, p);
    const int x = static_cast<int>(q.x), y = static_cast<int>(q.y);
    if (!(q.x >= 0.0f && q.y >= 0.0f) || x >= photo.width || y >= photo.height) continue;
    const glm::vec3 colour = PixelColour(photo, x, y);
    const bool hair_coloured = glm::length(colour - hair.colour) < glm::length(colour - hair.skin_colour);
    const bool is_hair = hair.head->At(x, y) * (1.0f - skin.At(x, y)) > 0.5f && hair_coloured;
    bins[static_cast<std::size_t>(bin)].push_back({height - ScalpRegion::RuleHairline(azimuth), is_hair});
  }
  std::array<bool, ScalpRegion::kShiftBins> measured{};
  int placed = 0;
  for (std::size_t b = 0; b < bins.size(); ++b) {
    float split = 0.0f;
    measured[b] = BestSplit(bins[b], split);
    // A hairline the photo puts far from any head's is more likely a mask's mistake.
    if (measured[b]) scalp.hairline_shift[b] = std::clamp(split, -0.8f, 0.4f), ++placed;
  }
  Spread(measured, scalp.hairline_shift);
  scalp.hairline_from_photo = placed > 0;
  return placed;
}

}  // namespace facerig::photo_texture
