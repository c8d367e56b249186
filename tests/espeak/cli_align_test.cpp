// `facerig align` in-process: a recording and its transcript give a track the
// player reads; a bad recording or command line writes nothing.
#include "cli/app.h"

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/runtime/io/audio_file.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/runtime/audio/features.h"
#include "facerig/runtime/io/phoneme_track_file.h"
#include "support/command_runner.h"
#include "support/test_audio.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

constexpr const char* kSentence = "My mother made maple muffins.";

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

test::CommandOutcome Align(const std::vector<std::string>& arguments) {
  std::vector<std::string> all = {"align"};
  all.insert(all.end(), arguments.begin(), arguments.end());
  return test::RunCommand(cli::RunFacerig, all);
}

// espeak-ng speech of kSentence as a WAV at 44.1 kHz: another rate than the reference's.
fs::path RecordingWav(const std::string& name) {
  EspeakOptions options;
  options.rate_wpm = 190;
  options.variant = "m3";
  EspeakPhonemeSource source(options);
  const SpeechLine line = source.Synthesize(kSentence, "en-us");
  const std::vector<float> resampled = ResampleAudio(PcmToFloat(line.audio), line.sample_rate, 44100);
  const fs::path path = test::OutputPath(name);
  test::WriteWav(path, FloatToPcm(resampled), 44100);
  return path;
}

TEST_CASE("facerig align: writes a phoneme track of the recording, naming it", "[espeak][cli_align]") {
  const fs::path wav = RecordingWav("align_recording.wav");
  const fs::path text_file = test::OutputPath("align_transcript.txt");
  WriteText(text_file, kSentence);
  const fs::path track = test::OutputPath("align_track.json");
  const fs::path report = test::OutputPath("align_report.json");
  fs::remove(track);
  const test::CommandOutcome outcome =
      Align({wav.string(), "--text-file", text_file.string(), "--voice", "en-us", "-o", track.string(), "--json",
             report.string()});
  INFO(outcome.error_output);
  REQUIRE(outcome.exit_code == 0);
  const PhonemeTrack read = ReadPhonemeTrack(track);
  CHECK(read.audio_path == "align_recording.wav");
  CHECK(read.line.text == kSentence);
  CHECK(read.line.language.view() == "en-us");
  REQUIRE(read.line.phonemes.size() > 15);
  const double duration = static_cast<double>(fs::file_size(wav) - 44) / 2.0 / 44100.0;
  CHECK(read.line.phonemes.back().start.count() <= duration + 1e-6);
  CHECK(read.line.phonemes.back().start.count() > 0.5 * duration);
  // A track in another folder names the recording by its absolute path.
  const fs::path elsewhere = test::OutputPath("align_elsewhere") / "track.json";
  fs::create_directories(elsewhere.parent_path());
  REQUIRE(Align({wav.string(), "--text", kSentence, "-o", elsewhere.string()}).exit_code == 0);
  CHECK(fs::path(ReadPhonemeTrack(elsewhere).audio_path) == fs::weakly_canonical(wav));
  const nlohmann::json json = nlohmann::json::parse(ReadInputText(report));
  CHECK(json["command"] == "align");
  CHECK(json["result"]["sample_rate"] == 44100);
  CHECK(json["result"]["phonemes"] == read.line.phonemes.size());
  CHECK(json["result"]["mode"] == "transcript");
  CHECK_THAT(outcome.error_output, !Contains("rough"));
}

TEST_CASE("facerig align: without a transcript, the rough mode, said on stderr and in the report", "[espeak][cli_align]") {
  const fs::path wav = RecordingWav("align_rough.wav");
  const fs::path track = test::OutputPath("align_rough_track.json");
  const fs::path report = test::OutputPath("align_rough_report.json");
  fs::remove(track);
  const test::CommandOutcome outcome = Align({wav.string(), "-o", track.string(), "--json", report.string()});
  INFO(outcome.error_output);
  REQUIRE(outcome.exit_code == 0);
  CHECK_THAT(outcome.error_output, Contains("rough mode"));
  const PhonemeTrack read = ReadPhonemeTrack(track);
  CHECK(read.audio_path == "align_rough.wav");
  CHECK(read.line.text.empty());
  REQUIRE(read.line.phonemes.size() >= 5);
  // The rough mode's symbols only: rest, closed, open, front, rounded, fricative.
  std::size_t open = 0;
  for (const Phoneme& phoneme : read.line.phonemes) {
    INFO(phoneme.symbol.view());
    const std::string symbol(phoneme.symbol.view());
    CHECK((symbol == "_" || symbol == "b" || symbol == "a" || symbol == "i" || symbol == "o" || symbol == "s"));
    open += phoneme.symbol.view() == "a" ? 1 : 0;
  }
  CHECK(open >= 1);
  const nlohmann::json json = nlohmann::json::parse(ReadInputText(report));
  CHECK(json["result"]["mode"] == "rough");
  CHECK(json["result"]["phonemes"] == read.line.phonemes.size());
  CHECK(json["result"]["sample_rate"] == 44100);
  // A bad recording is still an error naming it.
  const fs::path bad = test::OutputPath("align_rough_bad.wav");
  WriteText(bad, "RIFF but not really a wave file");
  const test::CommandOutcome failed = Align({bad.string(), "-o", track.string()});
  CHECK(failed.exit_code == 1);
  CHECK_THAT(failed.error_output, Contains(bad.string()));
}

TEST_CASE("facerig align: a bad recording is a clear error and nothing is written", "[espeak][cli_align]") {
  const fs::path bad = test::OutputPath("align_bad.wav");
  WriteText(bad, "RIFF but not really a wave file");
  const fs::path track = test::OutputPath("align_bad_track.json");
  fs::remove(track);
  const test::CommandOutcome outcome = Align({bad.string(), "--text", kSentence, "-o", track.string()});
  CHECK(outcome.exit_code == 1);
  CHECK_THAT(outcome.error_output, Contains(bad.string()));
  CHECK_THAT(outcome.error_output, Contains("not a readable audio file"));
  CHECK_FALSE(fs::exists(track));
  // Two transcripts: a usage error.
  CHECK(Align({bad.string(), "--text", "a", "--text-file", "b", "-o", track.string()}).exit_code == 2);
  // An unknown voice names the voice.
  const fs::path wav = RecordingWav("align_voice.wav");
  const test::CommandOutcome voice = Align({wav.string(), "--text", kSentence, "--voice", "xx-nope", "-o", track.string()});
  CHECK(voice.exit_code == 1);
  CHECK_THAT(voice.error_output, Contains("xx-nope"));
  CHECK_FALSE(fs::exists(track));
}

}  // namespace
}  // namespace facerig
