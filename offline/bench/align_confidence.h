// facerig-bench align: the match confidence of recordings with their own
// transcript, with another line's, and of white noise with a transcript: the
// distributions `facerig align --min-confidence` is chosen from.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "facerig/runtime/speech/phoneme_source.h"

struct ConfidenceBenchOptions {
  std::vector<std::string> recordings_dirs;  // real recordings (pocketsphinx layout)
  std::vector<std::string> sentences;        // en-us lines spoken by `recorder` as synthetic recordings
  double min_confidence = 0.0;               // the threshold to count against
};

// Prints the distributions and the pairs on the wrong side of the threshold; returns them as JSON.
nlohmann::json MeasureConfidence(const ConfidenceBenchOptions& options, facerig::PhonemeSource& recorder,
                                 facerig::PhonemeSource& aligner);
