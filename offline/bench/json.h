// The benchmarks' shared JSON output: one report per run, written atomically.
#pragma once

#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "facerig/runtime/error.h"
#include "facerig/runtime/files/atomic_file.h"

// Writes `report` to `path` (nothing when `path` is empty). Returns the exit
// code for main: 0, or 1 after printing why the file could not be written.
inline int WriteBenchJson(const std::string& path, const nlohmann::json& report) {
  if (path.empty()) return 0;
  try {
    facerig::WriteFileAtomically(path, report.dump(2) + "\n");
  } catch (const facerig::IoError& error) {
    std::fprintf(stderr, "facerig-bench: %s\n", error.what());
    return 1;
  }
  std::printf("wrote %s\n", path.c_str());
  return 0;
}
