#include "bench/align_silence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <random>

#include "bench/align_stream.h"
#include "bench/recordings.h"
#include "facerig/offline/speech/recording_alignment.h"
#include "facerig/runtime/io/audio_file.h"
#include "facerig/runtime/speech/phoneme_visemes.h"
#include "measure/alignment_scoring.h"
#include "measure/silence_insertion.h"

namespace {

using facerig::test::Quantile;

constexpr double kLeadSeconds = 1.0, kInnerSeconds = 0.6, kTrailSeconds = 1.0;

struct Condition {
  const char* name;
  facerig::test::SilenceLayout layout;
};
constexpr Condition kConditions[] = {{"trimmed", {0.0, 0.0, 0.0}},
                                     {"before", {kLeadSeconds, 0.0, 0.0}},
                                     {"inside", {0.0, kInnerSeconds, 0.0}},
                                     {"after", {0.0, 0.0, kTrailSeconds}},
                                     {"all three", {kLeadSeconds, kInnerSeconds, kTrailSeconds}}};

bool IsPause(const facerig::Phoneme& p) {
  const auto visemes = facerig::LookupPhonemeVisemes("en-us", p.symbol.view());
  return visemes && visemes->count > 0 && visemes->visemes[0] == facerig::Viseme::kSil;
}

std::size_t FirstSound(const facerig::SpeechLine& line, std::size_t from) {
  while (from < line.phonemes.size() && IsPause(line.phonemes[from])) ++from;
  return from;
}

struct Errors {
  std::vector<double> first, inner, boundaries;
  std::size_t lines = 0, skipped = 0;
};

nlohmann::json ErrorsJson(const Errors& e) {
  return {{"lines", e.lines},
          {"skipped_lines", e.skipped},
          {"first_phoneme_median_ms", 1000.0 * Quantile(e.first, 0.5)},
          {"first_phoneme_p90_ms", 1000.0 * Quantile(e.first, 0.9)},
          {"after_inner_pause_median_ms", 1000.0 * Quantile(e.inner, 0.5)},
          {"boundary_median_ms", 1000.0 * Quantile(e.boundaries, 0.5)},
          {"boundary_p90_ms", 1000.0 * Quantile(e.boundaries, 0.9)}};
}

using Aligner = std::function<facerig::RecordingAlignment(const facerig::AudioClip&, const std::string&)>;

Aligner MakeAligner(facerig::PhonemeSource& source, bool streaming, bool pauses, double chunk_ms) {
  if (streaming) {
    facerig::StreamingAlignmentParams params;
    params.pauses = pauses;
    return [&source, params, chunk_ms](const facerig::AudioClip& clip, const std::string& text) {
      return StreamAlign(source, clip, text, "en-us", chunk_ms, params);
    };
  }
  facerig::PhonemeAlignmentParams params;
  params.pauses = pauses;
  return [&source, params](const facerig::AudioClip& clip, const std::string& text) {
    return facerig::AlignRecording(source, clip, text, "en-us", params);
  };
}

Errors MeasureCondition(const SilenceBenchOptions& options, facerig::PhonemeSource& recorder, const Condition& condition,
                        const Aligner& align) {
  Errors errors;
  std::mt19937 random(7);
  for (const std::string& sentence : options.sentences) {
    const facerig::SpeechLine spoken = recorder.Synthesize(sentence, "en-us");
    const facerig::test::SilencedRecording r = facerig::test::WithSilence(spoken, condition.layout, random);
    const facerig::RecordingAlignment aligned = align(r.clip, sentence);
    const facerig::test::AlignmentScore score = facerig::test::ScoreAlignment(r.truth, aligned.alignment.line);
    ++errors.lines;
    if (!score.same_phonemes) {
      ++errors.skipped;
      continue;
    }
    errors.boundaries.insert(errors.boundaries.end(), score.boundary_errors.begin(), score.boundary_errors.end());
    const auto error_at = [&](std::size_t i) {
      return std::abs(aligned.alignment.line.phonemes[i].start.count() - r.truth.phonemes[i].start.count());
    };
    const std::size_t first = FirstSound(r.truth, 0);
    if (first < r.truth.phonemes.size()) errors.first.push_back(error_at(first));
    const std::size_t inner = r.inner > 0 ? FirstSound(r.truth, r.inner) : r.truth.phonemes.size();
    if (inner < r.truth.phonemes.size()) errors.inner.push_back(error_at(inner));
  }
  return errors;
}

// Real recordings: the first sound with 1 s of room noise put before the
// recording against its time without (plus 1 s): no exact truth, but the
// silence must not move it.
std::vector<double> RealLeadShifts(const SilenceBenchOptions& options, const Aligner& align) {
  std::vector<double> shifts;
  std::mt19937 random(11);
  for (const std::string& folder : options.recordings_dirs) {
    if (!std::filesystem::exists(TranscriptionFile(folder))) continue;
    for (const BenchRecording& recording : ReadTranscription(folder)) {
      const facerig::AudioClip plain = facerig::ReadAudioFile(recording.wav);
      facerig::AudioClip lead = plain;
      std::normal_distribution<float> noise(0.0f, 1.0f);
      float quietest = 1.0f;
      const auto window = static_cast<std::size_t>(0.02 * plain.sample_rate);
      for (std::size_t at = 0; at + window <= plain.samples.size(); at += window) {
        double sum = 0.0;
        for (std::size_t k = at; k < at + window; ++k) sum += static_cast<double>(plain.samples[k]) * plain.samples[k];
        quietest = std::min(quietest, static_cast<float>(std::sqrt(sum / static_cast<double>(window))));
      }
      std::vector<float> silence(static_cast<std::size_t>(kLeadSeconds * plain.sample_rate));
      for (float& s : silence) s = quietest * noise(random);
      lead.samples.insert(lead.samples.begin(), silence.begin(), silence.end());
      const facerig::SpeechLine a = align(plain, recording.text).alignment.line;
      const facerig::SpeechLine b = align(lead, recording.text).alignment.line;
      const std::size_t first = FirstSound(a, 0);
      if (first >= a.phonemes.size()) continue;
      shifts.push_back(std::abs(b.phonemes[first].start.count() - (a.phonemes[first].start.count() + kLeadSeconds)));
    }
  }
  return shifts;
}

}  // namespace

nlohmann::json MeasureSilence(const SilenceBenchOptions& options, facerig::PhonemeSource& recorder,
                              facerig::PhonemeSource& aligner) {
  std::printf("\nsilence: %zu en-us lines with %.1f s before, %.1f s inside (at the middle word), %.1f s after "
              "(room noise at -60 dBFS throughout); pauses off = the behaviour before pause handling\n\n",
              options.sentences.size(), kLeadSeconds, kInnerSeconds, kTrailSeconds);
  std::printf("| silence | aligner | pauses | first phoneme median / p90 | after the inner pause (median) | "
              "boundaries median / p90 |\n|---|---|---|---|---|---|\n");
  nlohmann::json json = nlohmann::json::object();
  for (const bool streaming : {false, true}) {
    for (const Condition& condition : kConditions) {
      for (const bool pauses : {false, true}) {
        const Errors e = MeasureCondition(options, recorder, condition,
                                          MakeAligner(aligner, streaming, pauses, options.chunk_ms));
        const nlohmann::json j = ErrorsJson(e);
        std::printf("| %s | %s | %s | %.0f / %.0f ms | %s | %.1f / %.1f ms |\n", condition.name,
                    streaming ? "streaming" : "offline", pauses ? "on" : "off", j["first_phoneme_median_ms"].get<double>(),
                    j["first_phoneme_p90_ms"].get<double>(),
                    e.inner.empty() ? "-" : (std::to_string(std::lround(j["after_inner_pause_median_ms"].get<double>())) + " ms").c_str(),
                    j["boundary_median_ms"].get<double>(), j["boundary_p90_ms"].get<double>());
        json[streaming ? "streaming" : "offline"][condition.name][pauses ? "pauses_on" : "pauses_off"] = j;
      }
    }
  }
  std::printf("\nreal recordings, 1 s of their own noise level put first: |first sound - (its time without + 1 s)|\n\n"
              "| aligner | pauses | median | p90 | max |\n|---|---|---|---|---|\n");
  for (const bool streaming : {false, true}) {
    for (const bool pauses : {false, true}) {
      const std::vector<double> shifts = RealLeadShifts(options, MakeAligner(aligner, streaming, pauses, options.chunk_ms));
      if (shifts.empty()) continue;
      std::printf("| %s | %s | %.0f ms | %.0f ms | %.0f ms |\n", streaming ? "streaming" : "offline", pauses ? "on" : "off",
                  1000.0 * Quantile(shifts, 0.5), 1000.0 * Quantile(shifts, 0.9), 1000.0 * Quantile(shifts, 1.0));
      json["real_lead"][streaming ? "streaming" : "offline"][pauses ? "pauses_on" : "pauses_off"] = {
          {"recordings", shifts.size()},
          {"median_ms", 1000.0 * Quantile(shifts, 0.5)},
          {"p90_ms", 1000.0 * Quantile(shifts, 0.9)},
          {"max_ms", 1000.0 * Quantile(shifts, 1.0)}};
    }
  }
  return json;
}
