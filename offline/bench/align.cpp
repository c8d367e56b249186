#include "bench/align.h"
#include "bench/align_confidence.h"
#include "bench/align_silence.h"
#include "bench/align_stream.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/common.h"
#include "bench/json.h"
#include "bench/recordings.h"
#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/offline/speech/recording_alignment.h"
#include "facerig/runtime/io/audio_file.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/runtime/speech/phoneme_visemes.h"
#include "facerig/runtime/alignment/streaming_alignment.h"
#include "measure/alignment_scoring.h"

namespace {

namespace fs = std::filesystem;

struct AlignBenchOptions {
  std::string corpus_dir = FACERIG_DEFAULT_CORPUS_DIR;
  std::vector<std::string> voices = {"en-us", "en", "pt-br", "pt", "es", "fr", "de",
                                     "it",    "fi", "nl",    "pl", "ru", "hi", "cmn"};
  std::size_t max_lines = 200;
  int recording_rate = 175, recording_pitch = 50;
  std::string recording_variant;
  int reference_rate = 140, reference_pitch = 75;
  std::string reference_variant = "f3";
  std::string json_path;
  double stream_chunk_ms = 0.0;  // > 0: StreamingAligner fed chunks of this length instead of AlignRecording
  // Real speech with transcripts (Debian pocketsphinx-testdata): `transcription` lines
  // "<s> words </s> (id)" beside id.wav.
  std::vector<std::string> recordings_dirs = {"/usr/share/pocketsphinx/test/data/librivox",
                                              "/usr/share/pocketsphinx/test/data/cards"};
  std::vector<std::string> sections = {"voices", "real", "silence", "confidence"};
  std::size_t silence_lines = 40, confidence_lines = 12;
  double min_confidence = facerig::kDefaultMinMatchConfidence;
};

void AddAlignBenchOptions(CLI::App& app, AlignBenchOptions& o) {
  app.add_option("--corpus", o.corpus_dir, "folder of <voice>.txt, a sentence per line (en.txt for en-us and en)");
  facerig::cli::AddCommaListOption(app, "--voices", o.voices, "espeak-ng voices (default: the 14 supported)");
  app.add_option("--lines", o.max_lines, "at most N sentences per voice (default 200)");
  app.add_option("--recording-rate", o.recording_rate, "words per minute of the 'recording' (default 175)");
  app.add_option("--recording-pitch", o.recording_pitch, "its pitch 0..100 (default 50)");
  app.add_option("--recording-variant", o.recording_variant, "its espeak-ng variant (default none)");
  app.add_option("--reference-rate", o.reference_rate, "words per minute of the aligned reference (default 140)");
  app.add_option("--reference-pitch", o.reference_pitch, "its pitch (default 75)");
  app.add_option("--reference-variant", o.reference_variant, "its variant (default f3)");
  app.add_option("--json", o.json_path, "write the results as JSON");
  app.add_option("--stream-chunk", o.stream_chunk_ms,
                 "align with the streaming aligner, the recording in chunks of MS milliseconds (default: offline)");
  facerig::cli::AddCommaListOption(app, "--recordings", o.recordings_dirs,
                 "folders of real recordings: a 'transcription' file (pocketsphinx format) beside ID.wav "
                 "(default: pocketsphinx-testdata's librivox and cards; skipped when missing)");
  facerig::cli::AddCommaListOption(app, "--sections", o.sections,
                 "what to measure: voices (the table per voice), real (the real recordings), silence (silence "
                 "before, inside and after the speech, pause handling on and off), confidence (match confidence of "
                 "matched and mismatched pairs and noise) (default: all)");
  app.add_option("--confidence-lines", o.confidence_lines,
                 "synthetic en-us recordings in the confidence section, each with every line's transcript (default 12)");
  app.add_option("--min-confidence", o.min_confidence, "the threshold the confidence section counts against "
                 "(default facerig align's)");
  app.add_option("--silence-lines", o.silence_lines, "en-us sentences in the silence section (default 40)");
}

bool Wants(const AlignBenchOptions& options, const std::string& section) {
  return std::find(options.sections.begin(), options.sections.end(), section) != options.sections.end();
}

std::vector<std::string> CorpusLines(const AlignBenchOptions& options, const std::string& voice) {
  fs::path file = fs::path(options.corpus_dir) / (voice + ".txt");
  if (!fs::exists(file)) file = fs::path(options.corpus_dir) / "en.txt";
  std::istringstream in(facerig::ReadInputText(file, std::uint64_t{16} << 20));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line) && lines.size() < options.max_lines;) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

facerig::EspeakOptions SourceOptions(int rate, int pitch, const std::string& variant) {
  facerig::EspeakOptions options;
  options.rate_wpm = rate;
  options.pitch = pitch;
  options.variant = variant;
  return options;
}

struct VoiceResult {
  std::size_t sentences = 0, mismatched = 0, bilabials = 0, bilabials_kept = 0;
  std::vector<double> errors;
  double audio_seconds = 0.0, align_seconds = 0.0;
};

VoiceResult MeasureVoice(const AlignBenchOptions& options, const std::string& voice,
                         facerig::PhonemeSource& recorder, facerig::PhonemeSource& aligner) {
  VoiceResult result;
  for (const std::string& sentence : CorpusLines(options, voice)) {
    const facerig::SpeechLine truth = recorder.Synthesize(sentence, voice);
    facerig::AudioClip clip;
    clip.sample_rate = truth.sample_rate;
    clip.samples = facerig::PcmToFloat(truth.audio);
    const facerig::RecordingAlignment aligned =
        options.stream_chunk_ms > 0.0 ? StreamAlign(aligner, clip, sentence, voice, options.stream_chunk_ms)
                                      : facerig::AlignRecording(aligner, clip, sentence, voice);
    const facerig::test::AlignmentScore score = facerig::test::ScoreAlignment(truth, aligned.alignment.line);
    ++result.sentences;
    if (!score.same_phonemes) {
      ++result.mismatched;  // the two renditions chose different phonemes: no exact truth
      continue;
    }
    result.errors.insert(result.errors.end(), score.boundary_errors.begin(), score.boundary_errors.end());
    result.bilabials += score.bilabials;
    result.bilabials_kept += score.bilabials_kept;
    result.audio_seconds += truth.audio_duration().count();
    result.align_seconds += aligned.seconds;
  }
  return result;
}

nlohmann::json VoiceJson(const VoiceResult& r) {
  using facerig::test::Quantile;
  return {{"sentences", r.sentences},
          {"mismatched_sentences", r.mismatched},
          {"boundaries", r.errors.size()},
          {"median_ms", 1000.0 * Quantile(r.errors, 0.5)},
          {"p90_ms", 1000.0 * Quantile(r.errors, 0.9)},
          {"max_ms", 1000.0 * Quantile(r.errors, 1.0)},
          {"bilabials", r.bilabials},
          {"bilabials_kept", r.bilabials_kept},
          {"audio_seconds", r.audio_seconds},
          {"ms_per_audio_second", r.audio_seconds > 0.0 ? 1000.0 * r.align_seconds / r.audio_seconds : 0.0}};
}

// --- real speech: no exact truth; the time per second of audio and whether
// each /p b m/ mouth closure overlaps the recording's quiet closure gap ---

// Log energy of 30 ms windows every 5 ms.
std::vector<double> EnergyEnvelope(const facerig::AudioClip& clip, double* hop_seconds) {
  *hop_seconds = 0.005;
  const auto hop = static_cast<std::size_t>(clip.sample_rate * *hop_seconds);
  const auto window = 6 * hop;
  std::vector<double> energy;
  for (std::size_t start = 0; start + window <= clip.samples.size(); start += hop) {
    double sum = 0.0;
    for (std::size_t i = start; i < start + window; ++i) sum += static_cast<double>(clip.samples[i]) * clip.samples[i];
    energy.push_back(std::log(sum / static_cast<double>(window) + 1e-12));
  }
  return energy;
}

// The mouth's closure for a /p b m/ as the track times it (recording time, s):
// from the phoneme's start (45 ms earlier for an unvoiced stop, whose closure
// precedes the burst) to its end (at least 30 ms).
struct Interval {
  double start = 0.0, end = 0.0;
};

Interval MouthClosure(const facerig::Phoneme& p, const facerig::PhonemeVisemes& visemes) {
  const double start = p.start.count();
  return {start - (visemes.has(facerig::PhonemeVisemes::kUnvoicedStop) ? 0.045 : 0.0),
          start + std::max(p.duration.count(), 0.030)};
}

// The quietest 30 ms of the envelope whose start lies in [from, to] s.
std::optional<Interval> QuietestGap(const std::vector<double>& energy, double hop, double from, double to) {
  const auto first = static_cast<std::ptrdiff_t>(std::floor(from / hop));
  const auto last = static_cast<std::ptrdiff_t>(std::ceil(to / hop));
  std::ptrdiff_t quietest = -1;
  for (std::ptrdiff_t i = std::max<std::ptrdiff_t>(first, 0); i <= last && i < static_cast<std::ptrdiff_t>(energy.size()); ++i) {
    if (quietest < 0 || energy[static_cast<std::size_t>(i)] < energy[static_cast<std::size_t>(quietest)]) quietest = i;
  }
  if (quietest < 0) return std::nullopt;
  const double start = static_cast<double>(quietest) * hop;
  return Interval{start, start + 0.030};
}

bool IsVowel(const facerig::Phoneme& p) {
  const auto visemes = facerig::LookupPhonemeVisemes("en-us", p.symbol.view());
  if (!visemes || visemes->count == 0) return false;
  using facerig::Viseme;
  const Viseme v = visemes->visemes[0];
  return v == Viseme::kAA || v == Viseme::kE || v == Viseme::kIH || v == Viseme::kOH || v == Viseme::kOU;
}

// Where the acoustic closure of phonemes[i] must lie: from the preceding
// vowel's middle to the next vowel's onset (the quiet gap then ends by it).
// Without a vowel on a side, 150 ms from the phoneme.
Interval VowelToVowel(const std::vector<facerig::Phoneme>& phonemes, std::size_t i) {
  Interval window{phonemes[i].start.count() - 0.150, phonemes[i].start.count() + 0.150};
  for (std::size_t j = i; j-- > 0;) {
    if (IsVowel(phonemes[j])) {
      window.start = (phonemes[j].start + 0.5 * phonemes[j].duration).count();
      break;
    }
  }
  for (std::size_t j = i + 1; j < phonemes.size(); ++j) {
    if (IsVowel(phonemes[j])) {
      window.end = phonemes[j].start.count();
      break;
    }
  }
  return window;
}

bool Overlap(const Interval& a, double shift, const std::optional<Interval>& b) {
  return b && a.start + shift < b->end && b->start < a.end + shift;
}

struct ClosureCounts {
  std::size_t bilabials = 0, near_start = 0, vowel_to_vowel = 0, vowel_to_vowel_late = 0;
};

// Each /p b m/'s mouth closure against two acoustic closures: the quietest
// 30 ms within 120 ms of its start (crude: a quiet /s/ or pause nearby wins),
// and the quietest 30 ms between the neighbouring vowels; the second also with
// the mouth 150 ms late (the gap still found on the track as aligned).
void CountClosures(const std::vector<facerig::Phoneme>& phonemes, const std::vector<double>& energy, double hop,
                   ClosureCounts* counts) {
  for (std::size_t i = 0; i < phonemes.size(); ++i) {
    const auto visemes = facerig::LookupPhonemeVisemes("en-us", phonemes[i].symbol.view());
    if (!visemes || visemes->count == 0 || visemes->visemes[0] != facerig::Viseme::kPP) continue;
    const Interval mouth = MouthClosure(phonemes[i], *visemes);
    const double start = phonemes[i].start.count();
    const Interval window = VowelToVowel(phonemes, i);
    const std::optional<Interval> gap = QuietestGap(energy, hop, window.start, std::max(window.start, window.end - 0.030));
    ++counts->bilabials;
    counts->near_start += Overlap(mouth, 0.0, QuietestGap(energy, hop, start - 0.120, start + 0.120));
    counts->vowel_to_vowel += Overlap(mouth, 0.0, gap);
    counts->vowel_to_vowel_late += Overlap(mouth, 0.150, gap);
  }
}

nlohmann::json MeasureRecordings(const AlignBenchOptions& options) {
  facerig::EspeakPhonemeSource source;  // the default voice and rate
  ClosureCounts counts;
  double audio_seconds = 0.0, align_seconds = 0.0;
  std::size_t recording_count = 0;
  for (const std::string& folder : options.recordings_dirs) {
    if (!fs::exists(TranscriptionFile(folder))) continue;
    for (const BenchRecording& recording : ReadTranscription(folder)) {
      const facerig::AudioClip clip = facerig::ReadAudioFile(recording.wav);
      const facerig::RecordingAlignment result = facerig::AlignRecording(source, clip, recording.text, "en-us");
      ++recording_count;
      audio_seconds += clip.duration_seconds();
      align_seconds += result.seconds;
      double hop = 0.0;
      const std::vector<double> energy = EnergyEnvelope(clip, &hop);
      CountClosures(result.alignment.line.phonemes, energy, hop, &counts);
    }
  }
  if (recording_count == 0) return nullptr;
  const double ms_per_second = audio_seconds > 0.0 ? 1000.0 * align_seconds / audio_seconds : 0.0;
  const auto share = [&](std::size_t n) { return counts.bilabials > 0 ? static_cast<double>(n) / static_cast<double>(counts.bilabials) : 0.0; };
  std::printf("\nreal speech: %zu recordings, %.1f s, %.1f ms per second of audio\n"
              "/p b m/ mouth closure over the acoustic closure (quietest 30 ms):\n"
              "  between the neighbouring vowels: %zu / %zu (%.0f%%; the mouth 150 ms late: %.0f%%)\n"
              "  within 120 ms of the phoneme (crude): %zu / %zu (%.0f%%)\n",
              recording_count, audio_seconds, ms_per_second, counts.vowel_to_vowel, counts.bilabials,
              100.0 * share(counts.vowel_to_vowel), 100.0 * share(counts.vowel_to_vowel_late), counts.near_start,
              counts.bilabials, 100.0 * share(counts.near_start));
  return {{"folders", options.recordings_dirs},
          {"recordings", recording_count},
          {"audio_seconds", audio_seconds},
          {"ms_per_audio_second", ms_per_second},
          {"bilabials", counts.bilabials},
          {"closure_overlap_share", share(counts.vowel_to_vowel)},
          {"closure_overlap_share_150ms_late", share(counts.vowel_to_vowel_late)},
          {"closure_overlap_share_within_120ms", share(counts.near_start)}};
}

// The table per voice; returns the voices' JSON and fills `all`.
nlohmann::json MeasureVoices(const AlignBenchOptions& options, facerig::PhonemeSource& recorder,
                             facerig::PhonemeSource& aligner, VoiceResult& all) {
  nlohmann::json voices = nlohmann::json::object();
  std::printf("| voice | sentences | boundaries | median | p90 | max | /p b m/ kept | ms per s of audio |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (const std::string& voice : options.voices) {
    const VoiceResult r = MeasureVoice(options, voice, recorder, aligner);
    const nlohmann::json j = VoiceJson(r);
    std::printf("| %s | %zu (%zu mismatched) | %zu | %.1f ms | %.1f ms | %.0f ms | %zu / %zu | %.1f |\n",
                voice.c_str(), r.sentences, r.mismatched, r.errors.size(), j["median_ms"].get<double>(),
                j["p90_ms"].get<double>(), j["max_ms"].get<double>(), r.bilabials_kept, r.bilabials,
                j["ms_per_audio_second"].get<double>());
    voices[voice] = j;
    all.sentences += r.sentences;
    all.mismatched += r.mismatched;
    all.bilabials += r.bilabials;
    all.bilabials_kept += r.bilabials_kept;
    all.errors.insert(all.errors.end(), r.errors.begin(), r.errors.end());
    all.audio_seconds += r.audio_seconds;
    all.align_seconds += r.align_seconds;
  }
  const nlohmann::json total = VoiceJson(all);
  std::printf("| all | %zu (%zu mismatched) | %zu | %.1f ms | %.1f ms | %.0f ms | %zu / %zu | %.1f |\n",
              all.sentences, all.mismatched, all.errors.size(), total["median_ms"].get<double>(),
              total["p90_ms"].get<double>(), total["max_ms"].get<double>(), all.bilabials_kept, all.bilabials,
              total["ms_per_audio_second"].get<double>());
  return voices;
}

int RunAlign(const AlignBenchOptions& options) {
  try {
    facerig::EspeakPhonemeSource recorder(
        SourceOptions(options.recording_rate, options.recording_pitch, options.recording_variant));
    facerig::EspeakPhonemeSource aligner(
        SourceOptions(options.reference_rate, options.reference_pitch, options.reference_variant));
    if (options.stream_chunk_ms > 0.0) std::printf("streaming, chunks of %.0f ms; ", options.stream_chunk_ms);
    std::printf("align: recording %d wpm pitch %d variant '%s'; reference %d wpm pitch %d variant '%s'\n\n",
                options.recording_rate, options.recording_pitch, options.recording_variant.c_str(),
                options.reference_rate, options.reference_pitch, options.reference_variant.c_str());
    VoiceResult all;
    const nlohmann::json voices =
        Wants(options, "voices") ? MeasureVoices(options, recorder, aligner, all) : nlohmann::json::object();
    const nlohmann::json total = VoiceJson(all);
    nlohmann::json silence = nullptr;
    if (Wants(options, "silence") && options.silence_lines > 0) {
      AlignBenchOptions en = options;
      en.max_lines = options.silence_lines;
      SilenceBenchOptions silence_options{CorpusLines(en, "en-us"), options.recordings_dirs,
                                          options.stream_chunk_ms > 0.0 ? options.stream_chunk_ms : 20.0};
      silence = MeasureSilence(silence_options, recorder, aligner);
    }
    nlohmann::json confidence = nullptr;
    if (Wants(options, "confidence")) {
      AlignBenchOptions en = options;
      en.max_lines = options.confidence_lines;
      confidence = MeasureConfidence({options.recordings_dirs, CorpusLines(en, "en-us"), options.min_confidence},
                                     recorder, aligner);
    }
    const nlohmann::json report = {
        {"recording", {{"rate_wpm", options.recording_rate}, {"pitch", options.recording_pitch},
                       {"variant", options.recording_variant}}},
        {"reference", {{"rate_wpm", options.reference_rate}, {"pitch", options.reference_pitch},
                       {"variant", options.reference_variant}}},
        {"note", "ms_per_audio_second includes synthesizing the reference"},
        {"voices", voices},
        {"all", total},
        {"real_speech", Wants(options, "real") ? MeasureRecordings(options) : nlohmann::json(nullptr)},
        {"silence", silence},
        {"confidence", confidence}};
    return WriteBenchJson(options.json_path, report);
  } catch (const std::exception& error) {
    return ReportBenchFailure(error);
  }
}

}  // namespace

int RunAlignBenchmark(int argc, char** argv) {
  return ParseAndRunBench<AlignBenchOptions>(argc, argv, "alignment of recordings to transcripts against exact truth",
                                             "facerig-bench align", AddAlignBenchOptions, RunAlign);
}
