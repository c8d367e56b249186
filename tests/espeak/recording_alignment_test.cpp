// Alignment with exact truth: espeak-ng speech in one voice and rate stands
// in for the recording; the transcript is aligned to it through a synthetic
// rendition in another voice variant, pitch and rate, and the boundaries found
// are compared with the ones the first synthesis reported.
#include "facerig/offline/speech/recording_alignment.h"

#include <iostream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/espeak/espeak_phoneme_source.h"
#include "alignment_sentences.h"
#include "measure/alignment_scoring.h"
#include "measure/silence_insertion.h"

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

// Real recordings start and end with silence and pause between phrases; the
// synthetic rendition has none of it. Stop closures are quiet in the
// rendition too: crossing the recording's silence on one of them moved the
// stop and the phonemes after it past the silence (p90 390 ms before).
TEST_CASE("AlignRecording: 1 s of silence before, 0.6 s inside and 1 s after keep the boundaries", "[espeak][align]") {
  EspeakPhonemeSource recorder(AlignmentVoice(175, 50, ""));
  EspeakPhonemeSource aligner(AlignmentVoice(140, 75, "f3"));
  std::mt19937 random(7);
  std::vector<double> errors;
  const std::vector<std::string>& sentences = AlignmentSentences();
  for (std::size_t s = 0; s < sentences.size() && s < 12; ++s) {
    INFO(sentences[s]);
    const test::SilencedRecording r =
        test::WithSilence(recorder.Synthesize(sentences[s], "en-us"), {1.0, 0.6, 1.0}, random);
    const RecordingAlignment result = AlignRecording(aligner, r.clip, sentences[s], "en-us");
    const test::AlignmentScore score = test::ScoreAlignment(r.truth, result.alignment.line);
    REQUIRE(score.same_phonemes);
    errors.insert(errors.end(), score.boundary_errors.begin(), score.boundary_errors.end());
  }
  const double median = test::Quantile(errors, 0.5), p90 = test::Quantile(errors, 0.9);
  std::cout << "alignment with silence: " << errors.size() << " boundaries, median " << median * 1000 << " ms, p90 "
            << p90 * 1000 << " ms\n";
  CHECK(median <= 0.020);
  CHECK(p90 <= 0.050);
}

}  // namespace
}  // namespace facerig
