// Measurement helpers shared by the offline algorithms, the tools and the
// benchmarks: one percentile rule, one median and one timer, so every report agrees.
#pragma once

#include <chrono>
#include <vector>

namespace facerig {

// Nearest-rank percentile: the smallest value with at least `fraction` of the
// values at or below it (fraction 0.5: the median, 1: the largest); 0 for an
// empty list.
double Percentile(std::vector<double> values, double fraction);

// The middle value (the upper one of an even count); 0 for an empty list. For
// robust scales and starts inside the algorithms (openings, rigid pieces).
float Median(std::vector<float> values);

// Wall-clock seconds since `start` (std::chrono::steady_clock).
double SecondsSince(std::chrono::steady_clock::time_point start);

}  // namespace facerig
