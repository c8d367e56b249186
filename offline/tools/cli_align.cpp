// `facerig align`: a recording and its transcript to a phoneme track. Built
// only with facerig::espeak (the transcript's reference rendition), which
// makes the `facerig` executable GPL-3.
#include "cli_commands.h"

#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>


#include "cli_common.h"
#include "cli_report.h"
#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/offline/recording_alignment.h"
#include "facerig/runtime/io/audio_file.h"
#include "facerig/runtime/io/input_file.h"
#include "facerig/runtime/speech/phoneme_track_file.h"

namespace facerig::cli {
namespace {

struct AlignOptions {
  std::string audio_path, text, text_file, voice = "en-us", output, report_path;
};

// The audio as the track names it: relative to the track's folder when it is
// inside it (readers refuse paths that leave a file's folder), else absolute
// (for people; the player then needs --audio).
std::string AudioPathForTrack(const std::string& audio, const std::string& track) {
  std::error_code error;
  const std::filesystem::path absolute_audio = std::filesystem::weakly_canonical(audio, error);
  const std::filesystem::path folder = std::filesystem::weakly_canonical(track, error).parent_path();
  const std::filesystem::path relative = std::filesystem::relative(absolute_audio, folder, error);
  const bool inside = !error && !relative.empty() && *relative.begin() != "..";
  return inside ? relative.generic_string() : absolute_audio.string();
}

CommandReport AlignReport(const AlignOptions& options, const AudioClip& clip, const RecordingAlignment& result) {
  const double audio_seconds = clip.duration_seconds();
  CommandReport report{"align",
                       {{"audio", options.audio_path}, {"text_file", options.text_file}},
                       {{"track", options.output}}};
  report.timings = {{"align", result.seconds}, {"total", result.seconds}};
  report.result = {{"audio_seconds", audio_seconds},
                   {"sample_rate", clip.sample_rate},
                   {"channels", clip.channels_in_file},
                   {"voice", options.voice},
                   {"phonemes", result.alignment.line.phonemes.size()},
                   {"reference_seconds", result.reference.audio_duration().count()},
                   {"path_cost", result.alignment.cost},
                   {"ms_per_audio_second", audio_seconds > 0.0 ? 1000.0 * result.seconds / audio_seconds : 0.0}};
  return report;
}

int RunAlign(const AlignOptions& options) {
  return RunWritingCommand([&] {
    CheckWritable({options.output, options.report_path});
    const std::string text = options.text_file.empty()
                                 ? options.text
                                 : ReadInputText(options.text_file, EspeakPhonemeSource::kMaxTextBytes);
    const AudioClip clip = ReadAudioFile(options.audio_path);
    EspeakPhonemeSource source;
    const RecordingAlignment result = AlignRecording(source, clip, text, options.voice);
    const CommandReport report = AlignReport(options, clip, result);
    WriteOutputSet([&](OutputSet& set) {
      const std::filesystem::path track = set.Add(options.output, OutputSet::Kind::kFile);
      WritePhonemeTrack(track, result.alignment.line, AudioPathForTrack(options.audio_path, options.output));
      CheckAfterWrite("track", track);
      WriteReport(set, options.report_path, report);
    });
    std::fprintf(stderr, "%s: %.2f s of audio, %zu phonemes aligned in %.2f s; wrote %s\n",
                 options.audio_path.c_str(), clip.duration_seconds(), result.alignment.line.phonemes.size(),
                 result.seconds, options.output.c_str());
    return 0;
  });
}

}  // namespace

void AddAlignCommand(CLI::App& facerig, CommandBody& body) {
  auto [app, options] = AddSubcommand<AlignOptions>(
      facerig, body, "align", "align a recording to its transcript: a phoneme track for the player",
      "The transcript is spoken by espeak-ng in --voice (the recording's language) and warped onto the "
      "recording; the track (facerig-phoneme-track JSON) names the audio file.",
      &RunAlign);
  app->add_option("AUDIO", options->audio_path, "the recording (WAV, FLAC, Ogg, AIFF, ...)")->required();
  // Exactly one of --text and --text-file.
  CLI::Option_group* transcript = app->add_option_group("transcript", "the words spoken in AUDIO");
  transcript->add_option("--text", options->text, "the transcript");
  transcript->add_option("--text-file", options->text_file, "a file holding the transcript (UTF-8)");
  transcript->require_option(1);
  app->add_option("--voice", options->voice, "espeak-ng voice of the recording's language (default en-us)");
  AddOutputOptions(*app, options->output, options->report_path, "the phoneme track to write (JSON)");
}

}  // namespace facerig::cli
