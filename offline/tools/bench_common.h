// Small helpers the facerig-bench benchmarks share: the failure message, the
// middle of a sample and process CPU time.
#pragma once

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <exception>
#include <vector>

// Prints why a benchmark failed; returns the exit code for main (1).
inline int ReportBenchFailure(const std::exception& error) {
  std::fprintf(stderr, "facerig-bench: %s\n", error.what());
  return 1;
}

// The middle value (the upper one of an even count), without a full sort.
// Unlike facerig::Percentile(values, 0.5), which takes the lower one.
inline double UpperMedian(std::vector<double> values) {
  std::nth_element(values.begin(), values.begin() + static_cast<long>(values.size() / 2), values.end());
  return values[values.size() / 2];
}

// Process CPU seconds (all threads) since `start`.
inline double CpuSecondsSince(std::clock_t start) {
  return static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
}
