// The default head's teeth: two arched rows, each tooth its own slightly
// convex crown with rounded biting corners, and their painted texture (ivory
// crowns, dark gaps between them, a scalloped gum line, the back teeth fading
// into the mouth's shadow). Both use one tooth layout along the arch, so the
// painted gaps fall where the geometry dips.
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <opencv2/core.hpp>

#include "default_head/albedo.h"
#include "default_head/angles.h"

namespace facerig::default_head {
namespace {

// Relative widths of the teeth from the midline back (incisors, canine,
// premolars, molars), as real crowns are proportioned.
constexpr std::array<double, 7> kUpperWidths = {8.5, 6.5, 7.5, 7.0, 6.5, 10.0, 9.0};
constexpr std::array<double, 7> kLowerWidths = {5.3, 5.9, 7.0, 7.0, 7.0, 11.0, 10.5};

// Texture rows: the upper row's band on the top half, the lower's below;
// within a band the gum side comes first for the upper row and last for the lower.
constexpr double kGumShare = 0.26;  // of a band's height, at a tooth's middle
constexpr double kBandEdge = 0.49;  // the upper row's biting edge; a texel short of the lower band

struct ToothPlace {
  double along = 0.0;   // 0 at a tooth's edge, 1 at its middle
  double depth = 0.0;   // 0 at the front teeth, 1 at the back of the arch
};

// Where `u` (0..1 along the whole arch, 0.5 the midline) falls on a tooth.
ToothPlace PlaceOnTooth(double u, bool upper) {
  const auto& widths = upper ? kUpperWidths : kLowerWidths;
  double total = 0.0;
  for (double w : widths) total += w;
  const double from_mid = std::abs(u - 0.5) * 2.0 * total;  // in width units
  double start = 0.0;
  for (double w : widths) {
    if (from_mid <= start + w) {
      const double f = (from_mid - start) / w;
      return {std::max(0.0, std::sin(kPi * f)), from_mid / total};
    }
    start += w;
  }
  return {0.0, 1.0};
}

// The biting edge rises a little at each tooth's corners.
double EdgeNotch(double along) { return 0.07 * std::pow(1.0 - along, 6.0); }

struct RowShape {
  double front, half_width, depth;  // the arch: z = front - depth s^2, x = half_width s
  double y_gum, y_edge, thickness;
  bool upper;
  double jaw;
};

// Where the sections of a row fall, as (s, u): u the fraction of the arch's
// length (0.5 the midline), s the arch parameter there. The front teeth, the
// ones a viewer sees, get four sections each (their corners, their middle),
// the back teeth two.
std::vector<glm::dvec2> SectionPlaces(const RowShape& row) {
  // Arc length along s, tabulated finely to invert it.
  constexpr int kTable = 2001;
  std::vector<double> length(kTable, 0.0);
  auto arch = [&](double s) { return glm::dvec2(row.half_width * s, row.front - row.depth * s * s); };
  for (int i = 1; i < kTable; ++i) {
    const auto k = static_cast<std::size_t>(i);
    length[k] = length[k - 1] + glm::length(arch(-1.0 + 2.0 * i / (kTable - 1)) - arch(-1.0 + 2.0 * (i - 1) / (kTable - 1)));
  }
  auto s_at = [&](double u) {
    const double target = u * length.back();
    const auto hi = std::lower_bound(length.begin(), length.end(), target);
    if (hi == length.begin()) return -1.0;
    if (hi == length.end()) return 1.0;
    const auto i = static_cast<double>(hi - length.begin());
    const double t = (target - *(hi - 1)) / std::max(*hi - *(hi - 1), 1e-12);
    return -1.0 + 2.0 * (i - 1.0 + t) / (kTable - 1);
  };
  const auto& widths = row.upper ? kUpperWidths : kLowerWidths;
  double total = 0.0;
  for (double w : widths) total += w;
  std::vector<double> half = {0.0};  // distances from the midline, in width units
  double start = 0.0;
  for (std::size_t t = 0; t < widths.size(); ++t) {
    const std::vector<double> steps = t < 3 ? std::vector<double>{0.15, 0.5, 0.85, 1.0} : std::vector<double>{0.5, 1.0};
    for (double f : steps) half.push_back(start + f * widths[t]);
    start += widths[t];
  }
  std::vector<glm::dvec2> places;
  for (auto it = half.rbegin(); it != half.rend(); ++it) places.push_back({0.0, 0.5 - 0.5 * *it / total});
  for (std::size_t i = 1; i < half.size(); ++i) places.push_back({0.0, 0.5 + 0.5 * half[i] / total});
  for (glm::dvec2& place : places) place.x = s_at(place.y);
  return places;
}

// One row: cross-sections (front gum, front edge, back edge, back gum) along
// the arch, closed into a band with end caps.
std::vector<Triangle> AddTeethRow(HeadGeometry& head, const RowShape& row) {
  const std::vector<glm::dvec2> places = SectionPlaces(row);
  const double band_gum = row.upper ? 0.0 : 1.0, band_edge = row.upper ? kBandEdge : 1.0 - kBandEdge;
  std::vector<std::array<std::uint32_t, 4>> sections;
  for (const glm::dvec2& place_on_arch : places) {
    const double s = place_on_arch.x, u = place_on_arch.y;
    const glm::dvec3 centre{row.half_width * s, 0.0, row.front - row.depth * s * s};
    const glm::dvec3 outward = glm::normalize(glm::dvec3(2.0 * row.depth * s, 0.0, row.half_width));
    const ToothPlace place = PlaceOnTooth(u, row.upper);
    const double bulge = 0.05 * std::sqrt(place.along);  // each crown convex
    const double towards_gum = row.upper ? 1.0 : -1.0;
    const double y_edge = row.y_edge + towards_gum * EdgeNotch(place.along);
    const glm::dvec3 front = centre + bulge * outward, back = centre - row.thickness * outward;
    const std::array<glm::dvec3, 4> corners = {front + glm::dvec3(0.0, row.y_gum, 0.0),
                                               front + glm::dvec3(0.0, y_edge, 0.0),
                                               back + glm::dvec3(0.0, y_edge, 0.0),
                                               back + glm::dvec3(0.0, row.y_gum, 0.0)};
    std::array<std::uint32_t, 4> section{};
    for (std::size_t k = 0; k < 4; ++k) {
      section[k] = AddVertex(head, corners[k]);
      head.jaw_weight[section[k]] = row.jaw;
      const bool gum = k == 0 || k == 3;
      head.teeth_uvs.push_back({u, gum ? band_gum : band_edge});
    }
    sections.push_back(section);
  }
  // Sections run from the character's right to left; for the upper row
  // (gum above the edge) (k, k+1) around the section then faces outwards.
  std::vector<Triangle> triangles;
  for (std::size_t i = 0; i + 1 < sections.size(); ++i) {
    const auto& a = sections[i];
    const auto& b = sections[i + 1];
    for (std::size_t k = 0; k < 4; ++k) {
      const std::size_t l = (k + 1) % 4;
      if (row.upper) {
        triangles.push_back({a[k], a[l], b[l]});
        triangles.push_back({a[k], b[l], b[k]});
      } else {
        triangles.push_back({a[k], b[l], a[l]});
        triangles.push_back({a[k], b[k], b[l]});
      }
    }
  }
  const auto& first = sections.front();
  const auto& last = sections.back();
  if (row.upper) {
    triangles.push_back({first[0], first[2], first[1]});
    triangles.push_back({first[0], first[3], first[2]});
    triangles.push_back({last[0], last[1], last[2]});
    triangles.push_back({last[0], last[2], last[3]});
  } else {
    triangles.push_back({first[0], first[1], first[2]});
    triangles.push_back({first[0], first[2], first[3]});
    triangles.push_back({last[0], last[2], last[1]});
    triangles.push_back({last[0], last[3], last[2]});
  }
  return triangles;
}

// The colour of one texel of a row's band: `v` 0 at the gum edge of the
// band, 1 at the biting edge.
cv::Vec3f ToothColour(double u, double v, bool upper) {
  const ToothPlace place = PlaceOnTooth(u, upper);
  const cv::Vec3f ivory = Bgr(0.90f, 0.86f, 0.74f), root = Bgr(0.84f, 0.76f, 0.58f), edge = Bgr(0.74f, 0.76f, 0.76f);
  const cv::Vec3f gum = Bgr(0.72f, 0.36f, 0.38f), gap = Bgr(0.20f, 0.09f, 0.09f);
  // The gum reaches down between the teeth (papillae) and arches over each crown.
  const double gum_line = kGumShare + 0.16 * std::pow(1.0 - place.along, 3.0);
  const double crown = std::clamp((v - gum_line) / (1.0 - gum_line), 0.0, 1.0);
  cv::Vec3f c = crown < 0.35 ? root * static_cast<float>(1.0 - crown / 0.35) + ivory * static_cast<float>(crown / 0.35)
                             : ivory;
  if (crown > 0.85) c = c * static_cast<float>(1.0 - (crown - 0.85) / 0.15 * 0.6) + edge * static_cast<float>((crown - 0.85) / 0.15 * 0.6);
  // Rounded crown sides: the gap between two teeth is dark, widest at the biting edge.
  const double gap_width = 0.10 + 0.18 * std::pow(crown, 4.0);
  const float dark = static_cast<float>(std::clamp((gap_width - place.along) / 0.08, 0.0, 1.0));
  c = c * (1.0f - dark) + gap * dark;
  const float on_gum = static_cast<float>(std::clamp((gum_line - v) / 0.03, 0.0, 1.0));
  c = c * (1.0f - on_gum) + gum * on_gum;
  // The back of the arch sits in the mouth's shadow.
  const float shadow = static_cast<float>(0.8 * std::clamp((place.depth - 0.2) / 0.45, 0.0, 1.0));
  return c * (1.0f - shadow) + gap * shadow;
}

}  // namespace

double AddTeeth(HeadGeometry& head) {
  // Placed from where the lips meet (their middle third), not the nominal
  // mouth height: the upper edge just below the lip line, the lower row behind
  // and below it, so closed lips and "oh" cover the lower row.
  double crease_z = 0.0, lip_y = 0.0;
  const std::size_t n = head.upper_lip.size();
  for (std::uint32_t v : head.upper_lip) crease_z = std::max(crease_z, head.positions[v].z);
  for (std::size_t i = n / 3; i < n - n / 3; ++i) lip_y += head.positions[head.upper_lip[i]].y / static_cast<double>(n - 2 * (n / 3));
  const double teeth_front = crease_z - 0.45;
  head.teeth_upper.first = static_cast<std::uint32_t>(head.positions.size());
  AddPart(head, "teeth_upper", AddTeethRow(head, {teeth_front, 1.85, 2.5, lip_y + 1.0, lip_y - 0.2, 0.5, true, 0.0}));
  head.teeth_upper.count = static_cast<std::uint32_t>(head.positions.size()) - head.teeth_upper.first;
  head.teeth_lower.first = static_cast<std::uint32_t>(head.positions.size());
  AddPart(head, "teeth_lower",
          AddTeethRow(head, {teeth_front - 0.5, 1.7, 2.3, lip_y - 1.5, lip_y - 0.6, 0.45, false, 1.0}));
  head.teeth_lower.count = static_cast<std::uint32_t>(head.positions.size()) - head.teeth_lower.first;
  return crease_z;
}

EncodedImage PaintTeethAlbedo() {
  const int size = kTeethTextureSize;
  cv::Mat teeth(size, size, CV_32FC3);
  for (int y = 0; y < size; ++y) {
    const double band = (y + 0.5) / size * 2.0;  // 0..1 upper band, 1..2 lower band
    const bool upper = band < 1.0;
    const double v = std::min(1.0, (upper ? band : 2.0 - band) / (2.0 * kBandEdge));  // 0 at the gum edge
    for (int x = 0; x < size; ++x) teeth.at<cv::Vec3f>(y, x) = ToothColour((x + 0.5) / size, v, upper);
  }
  return EncodeFloatBgrPng(teeth, "default_head_teeth.png");
}

}  // namespace facerig::default_head
