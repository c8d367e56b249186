// Per-dimension statistics of frame-major features, for their normalisation
// to zero mean and unit variance (the batch features and the streaming
// aligner's reference). Private to facerig::runtime.
#pragma once

#include <cstddef>
#include <span>

namespace facerig::detail {

struct DimensionStatistics {
  double mean = 0.0, variance = 0.0;
  // 1 / standard deviation; 0 for a (nearly) constant dimension.
  double scale() const;
};

// Mean and variance of dimension `d` over the frames of `values` (frame-major,
// `dimension` values a frame, at least one frame).
DimensionStatistics StatisticsOf(std::span<const float> values, std::size_t dimension, std::size_t d);

// Dimension `d` of every frame to (v - mean) * scale.
void Normalize(std::span<float> values, std::size_t dimension, std::size_t d, const DimensionStatistics& statistics);

}  // namespace facerig::detail
