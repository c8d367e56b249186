// What the output-set tests of the `facerig` commands look at in a folder:
// files' bytes, its entries, and the temporaries a run may leave.
#pragma once

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "facerig/runtime/io/output_set.h"

namespace facerig::test {

inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

inline void WriteText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// The folder's entry names, sorted.
inline std::vector<std::string> Names(const std::filesystem::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// The entries named as an OutputSet's temporaries.
inline std::vector<std::string> Temporaries(const std::filesystem::path& folder) {
  std::vector<std::string> names;
  for (const std::string& name : Names(folder)) {
    if (name.rfind(kTemporaryPrefix, 0) == 0) names.push_back(name);
  }
  return names;
}

}  // namespace facerig::test
