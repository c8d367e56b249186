// Alignment with exact truth: espeak-ng speech in one voice and rate stands
// in for the recording; the transcript is aligned to it through a synthetic
// rendition in another voice variant, pitch and rate, and the boundaries found
// are compared with the ones the first synthesis reported.
#include "facerig/offline/recording_alignment.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/runtime/speech/phoneme_visemes.h"

namespace facerig {
namespace {

const std::vector<std::string>& Sentences() {
  static const std::vector<std::string> sentences = {
      "Peter picked a peck of pickled peppers by the pond.",
      "My mother made maple muffins every Monday morning.",
      "Please pass me the paper plate and the plastic spoon.",
      "Five very friendly foxes visited the village fair.",
      "Bring both bottles of milk back before breakfast."};
  return sentences;
}

EspeakOptions Voice(int rate_wpm, int pitch, std::string variant) {
  EspeakOptions options;
  options.rate_wpm = rate_wpm;
  options.pitch = pitch;
  options.variant = std::move(variant);
  return options;
}

AudioClip AsRecording(const SpeechLine& line) {
  AudioClip clip;
  clip.sample_rate = line.sample_rate;
  clip.channels_in_file = 1;
  clip.samples = PcmToFloat(line.audio);
  return clip;
}

std::vector<std::string> Symbols(const SpeechLine& line) {
  std::vector<std::string> symbols;
  for (const Phoneme& p : line.phonemes) symbols.emplace_back(p.symbol.view());
  return symbols;
}

double Quantile(std::vector<double> values, double share) {
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(share * static_cast<double>(values.size() - 1))];
}

bool IsBilabial(const Phoneme& p, std::string_view language) {
  const auto visemes = LookupPhonemeVisemes(language, p.symbol.view());
  return visemes && visemes->count > 0 && visemes->visemes[0] == Viseme::kPP;
}

TEST_CASE("AlignRecording: boundaries within 20 ms (median) of the truth across voices and rates", "[espeak][align]") {
  EspeakPhonemeSource recorder(Voice(175, 50, ""));
  EspeakPhonemeSource aligner(Voice(140, 75, "f3"));
  std::vector<double> errors;
  double audio_seconds = 0.0, align_seconds = 0.0;
  std::size_t bilabials = 0, bilabials_closed = 0;
  for (const std::string& sentence : Sentences()) {
    INFO(sentence);
    const SpeechLine truth = recorder.Synthesize(sentence, "en-us");
    const RecordingAlignment result = AlignRecording(aligner, AsRecording(truth), sentence, "en-us");
    const SpeechLine& aligned = result.alignment.line;
    REQUIRE(Symbols(aligned) == Symbols(truth));  // same language: same phonemes
    audio_seconds += truth.audio_duration().count();
    align_seconds += result.seconds;
    for (std::size_t i = 0; i < truth.phonemes.size(); ++i) {
      const Phoneme& t = truth.phonemes[i];
      const Phoneme& a = aligned.phonemes[i];
      errors.push_back(std::abs(a.start.count() - t.start.count()));
      if (!IsBilabial(t, "en-us")) continue;
      ++bilabials;
      // Same class and overlapping the true closure.
      const double overlap = std::min(a.start + a.duration, t.start + t.duration).count() -
                             std::max(a.start, t.start).count();
      if (IsBilabial(a, "en-us") && overlap > 0.0) ++bilabials_closed;
    }
  }
  const double median = Quantile(errors, 0.5), p90 = Quantile(errors, 0.9);
  std::cout << "alignment: " << errors.size() << " boundaries, median " << median * 1000 << " ms, p90 " << p90 * 1000
            << " ms, max " << Quantile(errors, 1.0) * 1000 << " ms; " << 1000 * align_seconds / audio_seconds
            << " ms per second of audio; /p b m/ " << bilabials_closed << "/" << bilabials << "\n";
  CHECK(median <= 0.020);
  CHECK(p90 <= 0.050);
  CHECK(bilabials > 20);
  CHECK(bilabials_closed == bilabials);
}

}  // namespace
}  // namespace facerig
