// `facerig align`: a recording and its transcript to a phoneme track. Built
// only with facerig::espeak (the transcript's reference rendition), which
// makes the `facerig` executable GPL-3.
#include "cli/commands.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>

#include "cli/common.h"
#include "cli/options.h"
#include "cli/report.h"
#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/offline/speech/recording_alignment.h"
#include "facerig/offline/speech/transcript_markup.h"
#include "facerig/offline/geometry/stats.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/io/audio_file.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/runtime/audio/mouth.h"
#include "facerig/runtime/io/phoneme_track_file.h"

namespace facerig::cli {
namespace {

struct AlignOptions {
  std::string audio_path, text, text_file, voice = "en-us", output, report_path;
  double min_confidence = kDefaultMinMatchConfidence;
  bool force = false;
};

// The audio as the track names it: relative to the track's folder, which
// must hold it (files name other files only inside their own folder, and the
// player refuses the track otherwise); nullopt when it does not.
std::optional<std::string> AudioPathForTrack(const std::string& audio, const std::string& track) {
  std::error_code error;
  const std::filesystem::path absolute_audio = std::filesystem::weakly_canonical(std::filesystem::absolute(audio), error);
  const std::filesystem::path folder =
      std::filesystem::weakly_canonical(std::filesystem::absolute(track), error).parent_path();
  if (error) return std::nullopt;
  const std::filesystem::path relative = absolute_audio.lexically_relative(folder);
  const bool inside = !relative.empty() && *relative.begin() != ".." && relative.is_relative();
  if (!inside) return std::nullopt;
  return relative.generic_string();
}

bool IsRoughMode(const AlignOptions& options) { return options.text.empty() && options.text_file.empty(); }

CommandReport AlignReport(const AlignOptions& options, const AudioClip& clip, const SpeechLine& line, double seconds) {
  const double audio_seconds = clip.duration_seconds();
  CommandReport report{"align",
                       {{"audio", options.audio_path}, {"text_file", options.text_file}},
                       {{"track", options.output}}};
  report.timings = {{"align", seconds}, {"total", seconds}};
  report.result = {{"mode", IsRoughMode(options) ? "rough" : "transcript"},
                   {"audio_seconds", audio_seconds},
                   {"sample_rate", clip.sample_rate},
                   {"channels", clip.channels_in_file},
                   {"phonemes", line.phonemes.size()},
                   {"ms_per_audio_second", audio_seconds > 0.0 ? 1000.0 * seconds / audio_seconds : 0.0}};
  return report;
}

struct AlignOutcome {
  SpeechLine line;
  CommandReport report;
  double confidence = 1.0, tempo = 1.0;
  bool fits = true;  // the rough mode has no transcript to doubt
};

// The transcript's alignment, its details added to the report.
AlignOutcome AlignTranscript(const AlignOptions& options, const AudioClip& clip) {
  const PlainTranscript transcript = RemoveTranscriptMarkup(
      options.text_file.empty() ? options.text : ReadInputText(options.text_file, EspeakPhonemeSource::kMaxTextBytes));
  if (transcript.markup_removed) {
    std::fprintf(stderr, "%s: removed markup from the transcript (<s> </s> <sil> tags, the utterance id): \"%s\"\n",
                 options.text_file.empty() ? "--text" : options.text_file.c_str(), transcript.text.c_str());
  }
  EspeakPhonemeSource source;
  RecordingAlignment result = AlignRecording(source, clip, transcript.text, options.voice);
  CommandReport report = AlignReport(options, clip, result.alignment.line, result.seconds);
  report.result["voice"] = options.voice;
  report.result["reference_seconds"] = result.reference.audio_duration().count();
  report.result["path_cost"] = result.alignment.cost;
  report.result["pauses"] = result.alignment.pauses;
  report.result["transcript_markup_removed"] = transcript.markup_removed;
  report.result["confidence"] = result.alignment.confidence;
  report.result["tempo"] = result.alignment.tempo;
  report.result["min_confidence"] = options.min_confidence;
  report.result["forced"] = options.force;
  const bool fits = TranscriptFits(result.alignment, options.min_confidence);
  return {std::move(result.alignment.line), std::move(report), result.alignment.confidence, result.alignment.tempo, fits};
}

// The recording and the transcript do not seem to match: said, and nothing
// written unless --force.
bool RefuseMismatch(const AlignOptions& options, const AlignOutcome& outcome) {
  if (outcome.fits) return false;
  std::fprintf(stderr,
               "facerig: %s and the transcript do not seem to match (match confidence %.2f, at least %.2f wanted; "
               "the recording's speech lasts %.2f times the transcript's, %.1f-%.1f wanted): check that the "
               "transcript holds the recording's words%s\n",
               options.audio_path.c_str(), outcome.confidence, options.min_confidence, outcome.tempo,
               1.0 / kMaxTempoRatio, kMaxTempoRatio,
               options.force ? "; writing the track anyway (--force)" : "; --force writes the track anyway");
  return !options.force;
}

// The rough mode: a coarse mouth from the audio alone.
AlignOutcome RoughTrack(const AlignOptions& options, const AudioClip& clip) {
  const auto start = std::chrono::steady_clock::now();
  std::optional<SpeechLine> line = RoughMouthFromAudio(clip.samples, clip.sample_rate);
  if (!line) {
    throw IoError(IoErrorKind::kUnsupportedFormat, options.audio_path,
                  "sample rate " + std::to_string(clip.sample_rate) + " Hz is outside what the rough mode reads");
  }
  const double seconds = SecondsSince(start);
  CommandReport report = AlignReport(options, clip, *line, seconds);
  return {std::move(*line), std::move(report)};
}

int RunAlign(const AlignOptions& options) {
  const std::optional<std::string> audio_in_track = AudioPathForTrack(options.audio_path, options.output);
  if (!audio_in_track) {
    const std::filesystem::path suggestion =
        std::filesystem::path(options.audio_path).parent_path() / std::filesystem::path(options.output).filename();
    std::fprintf(stderr,
                 "facerig align: the track names its audio relative to its own folder, which must hold %s: write "
                 "it there (e.g. -o %s) or put the audio in the track's folder\n",
                 options.audio_path.c_str(), suggestion.string().c_str());
    return kUsageExitCode;
  }
  return RunWritingCommand([&] {
    CheckWritable({options.output, options.report_path});
    const AudioClip clip = ReadAudioFile(options.audio_path);
    const AlignOutcome outcome = IsRoughMode(options) ? RoughTrack(options, clip) : AlignTranscript(options, clip);
    if (RefuseMismatch(options, outcome)) return 1;
    const SpeechLine& line = outcome.line;
    const CommandReport& report = outcome.report;
    WriteOutputSet([&](OutputSet& set) {
      const std::filesystem::path track = set.Add(options.output, OutputSet::Kind::kFile);
      WritePhonemeTrack(track, line, *audio_in_track);
      CheckAfterWrite("track", track);
      WriteReport(set, options.report_path, report);
    });
    if (IsRoughMode(options)) {
      std::fprintf(stderr, "%s: no transcript: the rough mode, a coarse mouth from the audio alone "
                   "(no phonemes; p, b, m do not close the lips); give --text for lip-sync\n",
                   options.audio_path.c_str());
    }
    std::fprintf(stderr, "%s: %.2f s of audio, %zu phonemes %s in %.2f s; wrote %s\n", options.audio_path.c_str(),
                 clip.duration_seconds(), line.phonemes.size(), IsRoughMode(options) ? "(rough)" : "aligned",
                 report.timings.front().second, options.output.c_str());
    return 0;
  });
}

}  // namespace

void AddAlignCommand(CLI::App& facerig, CommandBody& body) {
  auto [app, options] = AddSubcommand<AlignOptions>(
      facerig, body, "align", "align a recording to its transcript: a phoneme track for the player",
      "The transcript is spoken by espeak-ng in --voice (the recording's language) and warped onto the "
      "recording; the track (facerig-phoneme-track JSON) names the audio file. Without a transcript: the "
      "rough mode (loudness and spectral shape to open/closed and a few vowel classes; no phonemes).",
      &RunAlign);
  app->add_option("AUDIO", options->audio_path, "the recording (WAV, FLAC, Ogg, AIFF, ...)")->required();
  // At most one of --text and --text-file; neither: the rough mode.
  CLI::Option_group* transcript = app->add_option_group(
      "transcript", "the words spoken in AUDIO; without them, the rough mode: a coarse mouth from the audio alone");
  transcript->add_option("--text", options->text, "the transcript");
  transcript->add_option("--text-file", options->text_file, "a file holding the transcript (UTF-8)");
  transcript->require_option(0, 1);
  app->add_option("--voice", options->voice, "espeak-ng voice of the recording's language (default en-us)");
  app->add_option("--min-confidence", options->min_confidence,
                  "below this match confidence (0..1) the recording and the transcript are taken not to match and "
                  "nothing is written (default " + std::to_string(kDefaultMinMatchConfidence).substr(0, 4) + ")")
      ->check(CLI::Range(-1.0, 1.0));
  app->add_flag("--force", options->force, "write the track even when the recording and the transcript do not "
                "seem to match");
  AddOutputOptions(*app, options->output, options->report_path, "the phoneme track to write (JSON)");
}

}  // namespace facerig::cli
