// The named, timed stages of a rig build: BuildRig's own (register,
// transfer, map, ...) and the command line's around them (load, landmarks,
// write), in one list for the report's timings.
#pragma once

#include <chrono>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "facerig/offline/geometry/stats.h"

namespace facerig {

// One named stage of the build and its wall-clock time.
struct BuildStage {
  std::string name;
  double seconds = 0.0;
};

// The time of the stage with this name (0 when absent), and of all stages.
double StageSeconds(std::span<const BuildStage> stages, std::string_view name);
double TotalSeconds(std::span<const BuildStage> stages);

// Runs body() and appends its wall-clock time to stages as `name`; returns
// what body returns.
template <typename Body>
auto TimeStage(std::vector<BuildStage>& stages, std::string_view name, Body&& body) {
  const auto start = std::chrono::steady_clock::now();
  if constexpr (std::is_void_v<decltype(body())>) {
    std::forward<Body>(body)();
    stages.push_back({std::string(name), SecondsSince(start)});
  } else {
    auto value = std::forward<Body>(body)();
    stages.push_back({std::string(name), SecondsSince(start)});
    return value;
  }
}

}  // namespace facerig
