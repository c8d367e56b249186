#include "audio/feature_statistics.h"

#include <algorithm>
#include <cmath>

namespace facerig::detail {

double DimensionStatistics::scale() const { return variance > 1e-12 ? 1.0 / std::sqrt(variance) : 0.0; }

DimensionStatistics StatisticsOf(std::span<const float> values, std::size_t dimension, std::size_t d) {
  const std::size_t frames = values.size() / dimension;
  double sum = 0.0, squares = 0.0;
  for (std::size_t f = 0; f < frames; ++f) {
    const double v = values[f * dimension + d];
    sum += v;
    squares += v * v;
  }
  DimensionStatistics statistics;
  statistics.mean = sum / static_cast<double>(frames);
  statistics.variance = std::max(0.0, squares / static_cast<double>(frames) - statistics.mean * statistics.mean);
  return statistics;
}

void Normalize(std::span<float> values, std::size_t dimension, std::size_t d, const DimensionStatistics& statistics) {
  const double scale = statistics.scale();
  for (std::size_t at = d; at < values.size(); at += dimension) {
    values[at] = static_cast<float>((values[at] - statistics.mean) * scale);
  }
}

}  // namespace facerig::detail
