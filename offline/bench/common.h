// Small helpers the facerig-bench benchmarks share: the command line, the
// failure message, the middle of a sample, process CPU time, shell quoting
// and the units of the re-meshed test faces.
#pragma once

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "cli/options.h"

// Parses a benchmark's arguments (argv[0] is the benchmark's name) into its
// options with `add_options`, then runs it. Returns the exit code: the
// parser's when the run stops there (--help, a bad value), else run's.
template <typename Options>
int ParseAndRunBench(int argc, char** argv, const char* description, const char* name,
                     void (*add_options)(CLI::App&, Options&), int (*run)(const Options&)) {
  Options options;
  CLI::App app(description, name);
  add_options(app, options);
  if (const std::optional<int> exit_code = facerig::cli::ParseCommandLine(app, argc - 1, argv + 1)) return *exit_code;
  return run(options);
}

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

// `text` in single quotes for the shell (a quote inside closes, escapes and reopens).
inline std::string ShellQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// Target units per centimetre of the re-meshed faces the register, build and
// cast benchmarks make: face f gets kUnitCycle[f % 3] (millimetres,
// centimetres, metres).
inline constexpr double kUnitCycle[3] = {10.0, 1.0, 0.01};
