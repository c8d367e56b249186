// A function given as a table of (x, y) knots with increasing x, linear
// between them and constant beyond the ends (painted hairlines by azimuth).
#pragma once

#include <cstddef>

namespace facerig {

template <typename T, std::size_t N>
T PiecewiseLinear(const T (&knots)[N][2], T x) {
  if (x <= knots[0][0]) return knots[0][1];
  for (std::size_t i = 1; i < N; ++i) {
    if (x <= knots[i][0]) {
      const T t = (x - knots[i - 1][0]) / (knots[i][0] - knots[i - 1][0]);
      return knots[i - 1][1] + t * (knots[i][1] - knots[i - 1][1]);
    }
  }
  return knots[N - 1][1];
}

}  // namespace facerig
