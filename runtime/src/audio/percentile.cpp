#include "audio/percentile.h"

#include <algorithm>
#include <cstddef>

namespace facerig::detail {

float PercentileInPlace(std::span<float> values, double share) {
  const auto at = static_cast<std::size_t>(share * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(at), values.end());
  return values[at];
}

}  // namespace facerig::detail
