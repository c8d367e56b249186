// facerig-bench align: recordings with silence before, inside and after the
// speech (as every real recording has), aligned with the pause handling on
// and off (the behaviour before it), offline and streaming.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "facerig/runtime/speech/phoneme_source.h"

struct SilenceBenchOptions {
  std::vector<std::string> sentences;       // the transcripts (en-us)
  std::vector<std::string> recordings_dirs; // real recordings (pocketsphinx layout)
  double chunk_ms = 20.0;                   // the streaming aligner's chunks
};

// Prints the comparison tables; returns them as JSON.
nlohmann::json MeasureSilence(const SilenceBenchOptions& options, facerig::PhonemeSource& recorder,
                              facerig::PhonemeSource& aligner);
