// Scoring an alignment against exact truth (both espeak-ng lines of one
// transcript and language): shared by the tests and `facerig-bench align`.
#pragma once

#include <cstddef>
#include <vector>

#include "facerig/runtime/speech/phoneme.h"

namespace facerig::test {

struct AlignmentScore {
  bool same_phonemes = false;          // the two lines name the same symbols in the same order
  std::vector<double> boundary_errors; // |aligned start - true start|, seconds, per phoneme (not those at 0)
  std::size_t bilabials = 0;           // /p b m/ (viseme PP) in the truth
  std::size_t bilabials_kept = 0;      // ... whose aligned phoneme is bilabial and overlaps the true interval
};

// Nothing but same_phonemes = false when the symbol sequences differ.
AlignmentScore ScoreAlignment(const SpeechLine& truth, const SpeechLine& aligned);

// The value at `share` (0..1) of the sorted values (nearest rank); 0 when empty.
double Quantile(std::vector<double> values, double share);

}  // namespace facerig::test
