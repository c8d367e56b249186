#include "audio/hann_window.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace facerig::detail {

std::vector<float> HannWindow(std::size_t size) {
  std::vector<float> window(size);
  const double span = std::max(1.0, static_cast<double>(size) - 1.0);
  for (std::size_t i = 0; i < size; ++i) {
    window[i] = static_cast<float>(0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * static_cast<double>(i) / span));
  }
  return window;
}

}  // namespace facerig::detail
