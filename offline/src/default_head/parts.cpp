// The separate parts of the default head, generated procedurally rather than
// subdivided: eyeballs (white, iris, pupil as UV-sphere zones), the upper and
// lower rows of teeth (default_head_teeth.cpp), the inner mouth (a bag hanging
// from the lip margins) and the tongue.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "default_head/internal.h"
#include "default_head/angles.h"

namespace facerig::default_head {
namespace {

// Quads between two rows of equal length (closed around when `wrap`);
// (a_i, b_i) -> triangles facing the side given by the row order.
void Strip(std::vector<Triangle>& out, const std::vector<std::uint32_t>& a,
           const std::vector<std::uint32_t>& b, bool wrap) {
  const std::size_t n = a.size();
  const std::size_t quads = wrap ? n : n - 1;
  for (std::size_t i = 0; i < quads; ++i) {
    const std::size_t j = (i + 1) % n;
    out.push_back({a[i], b[i], b[j]});
    out.push_back({a[i], b[j], a[j]});
  }
}

// A zone of an eyeball: rings at polar angles (from the gaze axis +Z) between
// `from` and `to`; a pole closes the zone when from == 0 or to == pi.
void AddEyeZone(HeadGeometry& head, int side, double from, double to, int rings,
                std::vector<Triangle>& triangles) {
  constexpr int kSegments = 24;
  const glm::dvec3 centre = Anatomy::EyeCentre(side);
  const double r = Anatomy::kEyeRadius;
  std::vector<std::vector<std::uint32_t>> rows;
  for (int i = 0; i <= rings; ++i) {
    const double theta = from + (to - from) * i / rings;
    std::vector<std::uint32_t> row;
    const bool pole = (i == 0 && from == 0.0) || (i == rings && to == kPi);
    if (pole) {
      row.push_back(AddVertex(head, centre + glm::dvec3(0.0, 0.0, std::cos(theta) * r)));
    } else {
      for (int k = 0; k < kSegments; ++k) {
        const double phi = 2.0 * kPi * k / kSegments;
        row.push_back(AddVertex(head, centre + r * glm::dvec3(std::sin(theta) * std::cos(phi),
                                                                std::sin(theta) * std::sin(phi),
                                                                std::cos(theta))));
      }
    }
    rows.push_back(std::move(row));
  }
  for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
    const auto& a = rows[i];
    const auto& b = rows[i + 1];
    // Going from the front pole backwards with phi counter-clockwise (seen
    // from the front), the outward faces are (a_k, a_k+1, b_k+1), (a_k, b_k+1, b_k).
    for (int k = 0; k < kSegments; ++k) {
      const auto k0 = static_cast<std::size_t>(k), k1 = static_cast<std::size_t>((k + 1) % kSegments);
      if (a.size() == 1) {
        triangles.push_back({a[0], b[k0], b[k1]});
      } else if (b.size() == 1) {
        triangles.push_back({a[k0], b[0], a[k1]});
      } else {
        triangles.push_back({a[k0], b[k0], b[k1]});
        triangles.push_back({a[k0], b[k1], a[k1]});
      }
    }
  }
}

}  // namespace

namespace {

void AddEyeballs(HeadGeometry& head) {
  const double r = Anatomy::kEyeRadius;
  const double iris = std::asin(Anatomy::kIrisRadius / r), pupil = std::asin(Anatomy::kPupilRadius / r);
  std::array<std::vector<Triangle>, 6> eye_parts;  // white L, R, iris L, R, pupil L, R
  const auto eyes_begin = static_cast<std::uint32_t>(head.positions.size());
  for (int zone = 0; zone < 3; ++zone) {
    for (int side = 0; side < 2; ++side) {
      auto& triangles = eye_parts[static_cast<std::size_t>(zone * 2 + side)];
      if (zone == 0) AddEyeZone(head, side, iris, kPi, 9, triangles);
      if (zone == 1) AddEyeZone(head, side, pupil, iris, 3, triangles);
      if (zone == 2) AddEyeZone(head, side, 0.0, pupil, 2, triangles);
    }
  }
  static const char* const kEyeParts[6] = {"eye_white_L", "eye_white_R", "iris_L", "iris_R", "pupil_L", "pupil_R"};
  for (std::size_t i = 0; i < 6; ++i) AddPart(head, kEyeParts[i], eye_parts[i]);
  head.eyeballs = {eyes_begin, static_cast<std::uint32_t>(head.positions.size()) - eyes_begin};
}

void AddInnerMouth(HeadGeometry& head) {
  const double mouth_y = Anatomy::kMouthY;
  // Inner mouth: rings hanging from the lip margin loop (right corner, upper
  // chain, left corner, lower chain reversed), each ring deeper, opening to a
  // bag and closing at the back. Corners are the skin's corner vertices.
  const std::uint32_t corner_r = head.control.mouth.corner_a, corner_l = head.control.mouth.corner_b;
  std::vector<std::uint32_t> loop = {corner_r};
  loop.insert(loop.end(), head.upper_lip.begin(), head.upper_lip.end());
  loop.push_back(corner_l);
  loop.insert(loop.end(), head.lower_lip.rbegin(), head.lower_lip.rend());
  std::vector<double> side_sign(loop.size(), 0.0);  // +1 upper, -1 lower, 0 corner
  for (std::size_t i = 1; i <= head.upper_lip.size(); ++i) side_sign[i] = 1.0;
  for (std::size_t i = head.upper_lip.size() + 2; i < loop.size(); ++i) side_sign[i] = -1.0;
  const double corner_x = head.positions[corner_l].x;
  struct Ring {
    double depth, height, width, follow;
  };
  static constexpr Ring kRings[] = {{0.0, 0.0, 1.0, 1.0},  {0.35, 0.5, 1.02, 0.85}, {0.9, 1.2, 1.05, 0.6},
                                    {1.7, 1.65, 1.05, 0.35}, {2.7, 1.8, 1.0, 0.15}, {3.6, 1.55, 0.9, 0.05},
                                    {4.3, 0.9, 0.65, 0.0},   {4.6, 0.0, 0.4, 0.0}};
  head.mouth_inner.first = static_cast<std::uint32_t>(head.positions.size());
  std::vector<std::vector<std::uint32_t>> rows;
  for (const Ring& ring : kRings) {
    std::vector<std::uint32_t> row;
    const double blend = std::min(1.0, ring.depth / 0.9);  // from the lip shape to the bag shape
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const glm::dvec3 lip = head.positions[loop[i]];
      const double x = lip.x * ring.width;
      const double across = std::clamp(std::abs(lip.x) / corner_x, 0.0, 1.0);
      const double profile = std::sqrt(std::max(0.0, 1.0 - std::pow(across, 4.0)));
      const double y = (1.0 - blend) * lip.y + blend * mouth_y + side_sign[i] * ring.height * profile;
      const std::uint32_t v = AddVertex(head, {x, y, lip.z - ring.depth});
      head.jaw_weight[v] = head.jaw_weight[loop[i]];
      head.inner_source.push_back(loop[i]);
      head.inner_follow.push_back(ring.follow);
      // The painted interior darkens with depth into the mouth.
      head.mouth_uvs.push_back({(static_cast<double>(i) + 0.5) / static_cast<double>(loop.size()),
                                ring.depth / kRings[std::size(kRings) - 1].depth});
      row.push_back(v);
    }
    rows.push_back(std::move(row));
  }
  head.mouth_inner.count = static_cast<std::uint32_t>(head.positions.size()) - head.mouth_inner.first;
  std::vector<Triangle> inner;
  // The loop runs clockwise seen from the front (right corner, over the top,
  // left corner, under the bottom); faces point into the mouth cavity.
  for (std::size_t k = 0; k + 1 < rows.size(); ++k) Strip(inner, rows[k], rows[k + 1], true);
  AddPart(head, "mouth_inner", inner);
}

// Tongue: a flattened ellipsoid on the floor of the mouth, on the jaw.
void AddTongue(HeadGeometry& head, double crease_z) {
  const double mouth_y = Anatomy::kMouthY;
  head.tongue.first = static_cast<std::uint32_t>(head.positions.size());
  const glm::dvec3 centre{0.0, mouth_y - 0.95, crease_z - 2.9};
  const glm::dvec3 radii{1.45, 0.5, 1.9};
  constexpr int kRingsT = 10, kSegmentsT = 20;
  std::vector<std::vector<std::uint32_t>> t_rows;
  for (int i = 0; i <= kRingsT; ++i) {
    const double theta = kPi * i / kRingsT;  // from the tip (+Z) backwards
    std::vector<std::uint32_t> row;
    const int count = (i == 0 || i == kRingsT) ? 1 : kSegmentsT;
    for (int k = 0; k < count; ++k) {
      const double phi = 2.0 * kPi * k / kSegmentsT;
      const glm::dvec3 unit{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
      const std::uint32_t v = AddVertex(head, centre + unit * radii);
      head.jaw_weight[v] = 1.0;
      row.push_back(v);
    }
    t_rows.push_back(std::move(row));
  }
  std::vector<Triangle> tongue;
  for (std::size_t i = 0; i + 1 < t_rows.size(); ++i) {
    const auto& a = t_rows[i];
    const auto& b = t_rows[i + 1];
    for (std::size_t k = 0; k < static_cast<std::size_t>(kSegmentsT); ++k) {
      const std::size_t l = (k + 1) % kSegmentsT;
      if (a.size() == 1) tongue.push_back({a[0], b[k], b[l]});
      else if (b.size() == 1) tongue.push_back({a[k], b[0], a[l]});
      else {
        tongue.push_back({a[k], b[k], b[l]});
        tongue.push_back({a[k], b[l], a[l]});
      }
    }
  }
  AddPart(head, "tongue", tongue);
  head.tongue.count = static_cast<std::uint32_t>(head.positions.size()) - head.tongue.first;
}

}  // namespace

std::uint32_t AddVertex(HeadGeometry& head, const glm::dvec3& p) {
  head.positions.push_back(p);
  head.jaw_weight.push_back(0.0);
  return static_cast<std::uint32_t>(head.positions.size() - 1);
}

void AddPart(HeadGeometry& head, const char* name, const std::vector<Triangle>& triangles) {
  head.parts.push_back({name, static_cast<std::uint32_t>(head.triangles.size()),
                        static_cast<std::uint32_t>(triangles.size())});
  head.triangles.insert(head.triangles.end(), triangles.begin(), triangles.end());
}

void AddParts(HeadGeometry& head) {
  AddEyeballs(head);
  const double crease_z = AddTeeth(head);
  AddInnerMouth(head);
  AddTongue(head, crease_z);
}

}  // namespace facerig::default_head
