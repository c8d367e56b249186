// The espeak tests' corpus (data/corpus/<voice>.txt) and pause phonemes.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "facerig/runtime/speech/phoneme.h"

namespace facerig::test {

// data/corpus/<voice>.txt, one sentence per line; the English voices share en.txt.
inline std::vector<std::string> Corpus(const std::string& voice) {
  const std::string file = voice == "en-us" || voice == "en" ? "en" : voice;
  std::ifstream in(std::filesystem::path(FACERIG_SOURCE_DIR) / "data" / "corpus" / (file + ".txt"));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

// espeak's pauses: "_" and its lengths, and the "||" between clauses.
inline bool IsPause(const Phoneme& p) { return p.symbol.view().front() == '_' || p.symbol.view() == "||"; }

}  // namespace facerig::test
