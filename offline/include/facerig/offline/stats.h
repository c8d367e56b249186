// Measurement helpers shared by the offline algorithms, the tools and the
// benchmarks: one percentile rule and one timer, so every report agrees.
#pragma once

#include <chrono>
#include <vector>

namespace facerig {

// Nearest-rank percentile: the smallest value with at least `fraction` of the
// values at or below it (fraction 0.5: the median, 1: the largest); 0 for an
// empty list.
double Percentile(std::vector<double> values, double fraction);

// Wall-clock seconds since `start` (std::chrono::steady_clock).
double SecondsSince(std::chrono::steady_clock::time_point start);

}  // namespace facerig
