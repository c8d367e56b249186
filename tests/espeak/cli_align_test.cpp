// `facerig align` in-process: a recording and its transcript give a track the
// player reads; a bad recording or command line writes nothing.
#include "cli/app.h"

#include <cstdint>
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

// The current folder set for a scope (commands given relative paths, as people type them).
class InFolder {
 public:
  explicit InFolder(const fs::path& folder) : previous_(fs::current_path()) { fs::current_path(folder); }
  ~InFolder() { fs::current_path(previous_); }
  InFolder(const InFolder&) = delete;
  InFolder& operator=(const InFolder&) = delete;

 private:
  fs::path previous_;
};

TEST_CASE("facerig align: the track names its audio relative to its folder, as the player reads it", "[espeak][cli_align]") {
  const fs::path folder = test::FreshOutputFolder("align_relative");
  fs::create_directories(folder / "takes");
  fs::copy_file(RecordingWav("align_relative.wav"), folder / "line.wav");
  fs::copy_file(folder / "line.wav", folder / "takes" / "take.wav");
  InFolder in_folder(folder);
  // "-o line.track.json": no folder given.
  const test::CommandOutcome plain = Align({"line.wav", "--text", kSentence, "-o", "line.track.json"});
  INFO(plain.error_output);
  REQUIRE(plain.exit_code == 0);
  const PhonemeTrack track = ReadPhonemeTrack("line.track.json");
  CHECK(track.audio_path == "line.wav");
  // What the player does with --track: the audio resolved inside the track's folder.
  const fs::path resolved = ResolveInsideFolder("line.track.json", track.audio_path, "audio");
  CHECK(resolved == fs::weakly_canonical(folder / "line.wav"));
  CHECK(ReadAudioFile(resolved).sample_rate == 44100);
  // The audio in a subfolder of the track's.
  REQUIRE(Align({"takes/take.wav", "--text", kSentence, "-o", "./take.track.json"}).exit_code == 0);
  CHECK(ReadPhonemeTrack("take.track.json").audio_path == "takes/take.wav");
  REQUIRE(Align({(folder / "line.wav").string(), "--text", kSentence, "-o", (folder / "abs.track.json").string()})
              .exit_code == 0);
  CHECK(ReadPhonemeTrack("abs.track.json").audio_path == "line.wav");
  // A track outside the audio's folder could not name it: refused before any work, nothing written.
  const test::CommandOutcome outside = Align({"line.wav", "--text", kSentence, "-o", "takes/line.track.json"});
  CHECK(outside.exit_code == 2);
  CHECK_THAT(outside.error_output, Contains("must hold line.wav"));
  CHECK_THAT(outside.error_output, Contains("-o line.track.json"));
  CHECK_FALSE(fs::exists("takes/line.track.json"));
}

TEST_CASE("facerig align: pocketsphinx markup in the transcript is not spoken", "[espeak][cli_align]") {
  const fs::path wav = RecordingWav("align_markup.wav");
  const fs::path text_file = test::OutputPath("align_markup.txt");
  WriteText(text_file, "<s> my mother made maple muffins </s> (mother-01)\n");
  const fs::path track = test::OutputPath("align_markup_track.json");
  const fs::path report = test::OutputPath("align_markup_report.json");
  const test::CommandOutcome outcome =
      Align({wav.string(), "--text-file", text_file.string(), "-o", track.string(), "--json", report.string()});
  INFO(outcome.error_output);
  REQUIRE(outcome.exit_code == 0);
  CHECK_THAT(outcome.error_output, Contains("removed markup"));
  const PhonemeTrack marked = ReadPhonemeTrack(track);
  CHECK(marked.line.text == "my mother made maple muffins");
  const nlohmann::json json = nlohmann::json::parse(ReadInputText(report));
  CHECK(json["result"]["transcript_markup_removed"] == true);
  // The same phonemes as the plain transcript's.
  const fs::path plain_track = test::OutputPath("align_markup_plain.json");
  REQUIRE(Align({wav.string(), "--text", "my mother made maple muffins", "-o", plain_track.string(), "--json",
                 report.string()}).exit_code == 0);
  CHECK(ReadPhonemeTrack(plain_track).line.phonemes.size() == marked.line.phonemes.size());
  CHECK(nlohmann::json::parse(ReadInputText(report))["result"]["transcript_markup_removed"] == false);
}

const fs::path kLibrivox = "/usr/share/pocketsphinx/test/data/librivox";

TEST_CASE("facerig align: a transcript that does not match the recording is refused, unless --force", "[espeak][cli_align]") {
  const fs::path recording = kLibrivox / "sense_and_sensibility_01_austen_64kb-0880.wav";
  INFO("needs Debian pocketsphinx-testdata (scripts/install-deps.sh): " << recording);
  REQUIRE(fs::exists(recording));
  const fs::path folder = test::FreshOutputFolder("align_mismatch");
  fs::copy_file(recording, folder / "line.wav");
  const std::string wav = (folder / "line.wav").string();
  const std::string track = (folder / "line.track.json").string(), report = (folder / "report.json").string();
  // Its own words: written, the confidence in the report.
  const test::CommandOutcome own =
      Align({wav, "--text", "he was not an ill disposed young man", "-o", track, "--json", report});
  INFO(own.error_output);
  REQUIRE(own.exit_code == 0);
  nlohmann::json json = nlohmann::json::parse(ReadInputText(report));
  CHECK(json["result"]["confidence"].get<double>() >= json["result"]["min_confidence"].get<double>());
  CHECK(json["result"]["forced"] == false);
  fs::remove(track);
  fs::remove(report);
  // Another recording's words: refused, saying so, nothing written.
  const std::string other = "ten of clubs";  // a `cards` line: the wrong file
  const test::CommandOutcome refused = Align({wav, "--text", other, "-o", track, "--json", report});
  CHECK(refused.exit_code == 1);
  CHECK_THAT(refused.error_output, Contains("do not seem to match"));
  CHECK_THAT(refused.error_output, Contains("--force"));
  CHECK_THAT(refused.error_output, !Contains("finite"));
  CHECK_FALSE(fs::exists(track));
  CHECK_FALSE(fs::exists(report));
  // --force writes it, a valid track, and says it was forced.
  const test::CommandOutcome forced = Align({wav, "--text", other, "-o", track, "--json", report, "--force"});
  INFO(forced.error_output);
  REQUIRE(forced.exit_code == 0);
  CHECK_THAT(forced.error_output, Contains("do not seem to match"));
  json = nlohmann::json::parse(ReadInputText(report));
  CHECK(json["result"]["forced"] == true);
  // Refused by the confidence or by the tempo (the two rules of the match).
  const double tempo = json["result"]["tempo"].get<double>();
  CHECK((json["result"]["confidence"].get<double>() < json["result"]["min_confidence"].get<double>() ||
         tempo < 0.5 || tempo > 2.0));
  CHECK(ReadPhonemeTrack(track).line.phonemes.size() > 5);
  // 3 s of white noise with a transcript.
  std::vector<float> noise(3 * 16000);
  std::uint32_t state = 5;
  for (float& v : noise) {
    state = state * 1664525u + 1013904223u;
    v = 0.2f * (static_cast<float>(state >> 8) / 8388608.0f - 1.0f);
  }
  test::WriteWav(folder / "noise.wav", FloatToPcm(noise), 16000);
  const test::CommandOutcome on_noise =
      Align({(folder / "noise.wav").string(), "--text", other, "-o", (folder / "noise.track.json").string()});
  CHECK(on_noise.exit_code == 1);
  CHECK_THAT(on_noise.error_output, Contains("do not seem to match"));
}

}  // namespace
}  // namespace facerig
