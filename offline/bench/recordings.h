// Real recordings with transcripts in pocketsphinx's layout (Debian
// pocketsphinx-testdata): a transcription file of "<s> words </s> (ID)" lines
// beside ID.wav. Read by facerig-bench align and av-sync.
#pragma once

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "facerig/runtime/files/input_file.h"

struct BenchRecording {
  std::string id, text;  // text in lower case, without <s> </s>
  std::filesystem::path wav;
};

// "transcription", or "<folder name>.transcription" when that is missing.
inline std::filesystem::path TranscriptionFile(const std::filesystem::path& folder) {
  const std::filesystem::path plain = folder / "transcription";
  return std::filesystem::exists(plain) ? plain : folder / (folder.filename().string() + ".transcription");
}

// Throws IoError when the transcription cannot be read.
inline std::vector<BenchRecording> ReadTranscription(const std::filesystem::path& folder) {
  std::vector<BenchRecording> recordings;
  std::istringstream in(facerig::ReadInputText(TranscriptionFile(folder), std::uint64_t{1} << 20));
  for (std::string line; std::getline(in, line);) {
    const std::size_t open = line.rfind('('), close = line.rfind(')');
    if (open == std::string::npos || close == std::string::npos || close < open) continue;
    std::string text = line.substr(0, open);
    for (const std::string tag : {"<s>", "</s>"}) {
      for (std::size_t at = text.find(tag); at != std::string::npos; at = text.find(tag)) text.erase(at, tag.size());
    }
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const std::string id = line.substr(open + 1, close - open - 1);
    recordings.push_back({id, text, folder / (id + ".wav")});
  }
  return recordings;
}
