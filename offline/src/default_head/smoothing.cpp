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
#include "geometry/mesh_edges.h"

namespace facerig::default_head {
namespace {

constexpr double kStep = 0.5;  // of the way to the neighbours' mean, per iteration

}  // namespace

SkinSmoother::SkinSmoother(const HeadGeometry& head) : fixed_(head.skin_count, 0) {
  const RawPart& skin = head.parts.front();
  const auto skin_triangles =
      std::span<const Triangle>(head.triangles).subspan(skin.first_triangle, skin.triangle_count);
  VertexNeighbours(head.skin_count, skin_triangles, neighbour_begin_, neighbours_);
  for (const BoundarySide& side : BoundarySides(skin_triangles)) fixed_[side.a] = fixed_[side.b] = 1;
}

template <typename T>
void SkinSmoother::SmoothField(std::vector<T>& field, int iterations) const {
  std::vector<T> next(field.begin(), field.begin() + static_cast<std::ptrdiff_t>(fixed_.size()));
  for (int i = 0; i < iterations; ++i) {
    for (std::size_t v = 0; v < fixed_.size(); ++v) {
      const std::uint32_t begin = neighbour_begin_[v], end = neighbour_begin_[v + 1];
      if (fixed_[v] || begin == end) continue;
      T mean = T(0.0);
      for (std::uint32_t k = begin; k < end; ++k) mean += field[neighbours_[k]];
      mean /= static_cast<double>(end - begin);
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
