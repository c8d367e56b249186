// Smoothing of control-authored fields over the dense skin. Two linear
// subdivision steps leave a field (a displacement, a jaw weight) piecewise
// linear on the control triangles, and the two Loop steps after them round
// its kinks over only a fraction of a control edge: an expression then bends
// the skin along the long control edges (nose wing to mouth corner to jaw)
// into a visible crease. Positions do not show it because the skin is
// projected onto the sculpt; deltas and weights are not, so they are smoothed
// here. The openings' margins and the neck rim stay fixed, so lips and lids
// still meet exactly and the inner mouth still follows its lip vertices.
#include <algorithm>
#include <cstddef>
#include <map>
#include <utility>

#include "default_head/internal.h"

namespace facerig::default_head {
namespace {

constexpr double kStep = 0.5;  // of the way to the neighbours' mean, per iteration

}  // namespace

SkinSmoother::SkinSmoother(const HeadGeometry& head)
    : neighbours_(head.skin_count), fixed_(head.skin_count, 0) {
  const RawPart& skin = head.parts.front();
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edge_use;
  for (std::uint32_t t = skin.first_triangle; t < skin.first_triangle + skin.triangle_count; ++t) {
    const Triangle& tri = head.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
      ++edge_use[{std::min(a, b), std::max(a, b)}];
    }
  }
  for (const auto& [edge, uses] : edge_use) {
    neighbours_[edge.first].push_back(edge.second);
    neighbours_[edge.second].push_back(edge.first);
    if (uses == 1) fixed_[edge.first] = fixed_[edge.second] = 1;
  }
}

template <typename T>
void SkinSmoother::SmoothField(std::vector<T>& field, int iterations) const {
  std::vector<T> next(field.begin(), field.begin() + static_cast<std::ptrdiff_t>(neighbours_.size()));
  for (int i = 0; i < iterations; ++i) {
    for (std::size_t v = 0; v < neighbours_.size(); ++v) {
      if (fixed_[v] || neighbours_[v].empty()) continue;
      T mean = T(0.0);
      for (std::uint32_t u : neighbours_[v]) mean += field[u];
      mean /= static_cast<double>(neighbours_[v].size());
      next[v] = field[v] + kStep * (mean - field[v]);
    }
    std::copy(next.begin(), next.end(), field.begin());
  }
}

void SkinSmoother::Smooth(std::vector<double>& field, int iterations) const { SmoothField(field, iterations); }
void SkinSmoother::Smooth(std::vector<glm::dvec3>& field, int iterations) const {
  SmoothField(field, iterations);
}

}  // namespace facerig::default_head
