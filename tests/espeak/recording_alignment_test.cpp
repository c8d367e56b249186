// Alignment with exact truth: espeak-ng speech in one voice and rate stands
// in for the recording; the transcript is aligned to it through a synthetic
// rendition in another voice variant, pitch and rate, and the boundaries found
// are compared with the ones the first synthesis reported.
#include "facerig/offline/speech/recording_alignment.h"

#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/espeak/espeak_phoneme_source.h"
#include "alignment_sentences.h"
#include "measure/alignment_scoring.h"

namespace facerig {
namespace {

using test::AlignmentSentences;
using test::AlignmentVoice;

AudioClip AsRecording(const SpeechLine& line) {
  AudioClip clip;
  clip.sample_rate = line.sample_rate;
  clip.channels_in_file = 1;
  clip.samples = PcmToFloat(line.audio);
  return clip;
}

TEST_CASE("AlignRecording: boundaries within 20 ms (median) of the truth across voices and rates", "[espeak][align]") {
  EspeakPhonemeSource recorder(AlignmentVoice(175, 50, ""));
  EspeakPhonemeSource aligner(AlignmentVoice(140, 75, "f3"));  // a female voice, higher, 20% slower
  std::vector<double> errors;
  double audio_seconds = 0.0, align_seconds = 0.0;
  std::size_t bilabials = 0, bilabials_kept = 0;
  for (const std::string& sentence : AlignmentSentences()) {
    INFO(sentence);
    const SpeechLine truth = recorder.Synthesize(sentence, "en-us");
    const RecordingAlignment result = AlignRecording(aligner, AsRecording(truth), sentence, "en-us");
    const test::AlignmentScore score = test::ScoreAlignment(truth, result.alignment.line);
    REQUIRE(score.same_phonemes);  // same language: same phonemes
    errors.insert(errors.end(), score.boundary_errors.begin(), score.boundary_errors.end());
    bilabials += score.bilabials;
    bilabials_kept += score.bilabials_kept;
    audio_seconds += truth.audio_duration().count();
    align_seconds += result.seconds;
  }
  const double median = test::Quantile(errors, 0.5), p90 = test::Quantile(errors, 0.9);
  std::cout << "alignment: " << errors.size() << " boundaries, median " << median * 1000 << " ms, p90 " << p90 * 1000
            << " ms, max " << test::Quantile(errors, 1.0) * 1000 << " ms; " << 1000 * align_seconds / audio_seconds
            << " ms per second of audio; /p b m/ " << bilabials_kept << "/" << bilabials << "\n";
  CHECK(median <= 0.020);
  CHECK(p90 <= 0.050);
  CHECK(bilabials > 20);
  CHECK(bilabials_kept == bilabials);
}

}  // namespace
}  // namespace facerig
