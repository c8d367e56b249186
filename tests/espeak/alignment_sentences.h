// The transcripts and espeak-ng voices the alignment tests use for their
// exact truth: one voice speaks the "recording", another the reference.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "facerig/espeak/espeak_phoneme_source.h"

namespace facerig::test {

inline const std::vector<std::string>& AlignmentSentences() {
  static const std::vector<std::string> sentences = {
      "Peter picked a peck of pickled peppers by the pond.",
      "My mother made maple muffins every Monday morning.",
      "Please pass me the paper plate and the plastic spoon.",
      "Five very friendly foxes visited the village fair.",
      "Bring both bottles of milk back before breakfast."};
  return sentences;
}

inline EspeakOptions AlignmentVoice(int rate_wpm, int pitch, std::string variant) {
  EspeakOptions options;
  options.rate_wpm = rate_wpm;
  options.pitch = pitch;
  options.variant = std::move(variant);
  return options;
}

}  // namespace facerig::test
