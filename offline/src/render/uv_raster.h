// Texels under a triangle laid out in a texture: how the painted textures
// (the built-in head's, the eyes') learn which surface point each texel shows.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/vec2.hpp>

namespace facerig {

// Calls visit(x, y, w0, w1, w2) for every texel centre (x, y) of a size x size
// texture inside the triangle p (texel coordinates: texel (x, y)'s centre is
// at (x, y)), with its barycentrics, as a renderer interpolates UVs: linearly
// in the triangle. Degenerate triangles visit nothing. Only rows in
// [row_begin, row_end) are visited: threads that each own a band of rows
// can share one texture.
template <typename Visit>
void ForEachTexelIn(const glm::dvec2 (&p)[3], int size, Visit&& visit, int row_begin = 0, int row_end = 1 << 30) {
  const double area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
  if (!(std::abs(area) >= 1e-12)) return;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].x, p[1].x, p[2].x}))));
  const int x1 = std::min(size - 1, static_cast<int>(std::ceil(std::max({p[0].x, p[1].x, p[2].x}))));
  const int y0 = std::max(row_begin, static_cast<int>(std::floor(std::min({p[0].y, p[1].y, p[2].y}))));
  const int y1 = std::min(std::min(size, row_end) - 1, static_cast<int>(std::ceil(std::max({p[0].y, p[1].y, p[2].y}))));
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const glm::dvec2 q{x, y};
      const double w1 = ((q.x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (q.y - p[0].y)) / area;
      const double w2 = ((p[1].x - p[0].x) * (q.y - p[0].y) - (q.x - p[0].x) * (p[1].y - p[0].y)) / area;
      const double w0 = 1.0 - w1 - w2;
      if (w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9) continue;
      visit(x, y, w0, w1, w2);
    }
  }
}

}  // namespace facerig
