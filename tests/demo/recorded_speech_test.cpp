// The player speaking a recording: --audio with its transcript (aligned at
// start) or with a phoneme track; headless frames and WAV on one timeline.
#include "recorded_speech.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/offline/io/template_folder.h"
#include "facerig/runtime/error.h"
#include "facerig/runtime/io/audio_file.h"
#include "facerig/runtime/audio/features.h"
#include "facerig/runtime/io/phoneme_track_file.h"
#include "headless_player.h"
#include "media_writer.h"
#include "player_options.h"
#include "support/test_audio.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;
using player::ParseOptions;
using player::PlayerOptions;
using player::UsageError;

constexpr const char* kSentence = "Bobby made a map.";

// espeak-ng speech in another voice and rate, at 44.1 kHz, as the "recording".
fs::path RecordingWav(const fs::path& folder) {
  EspeakOptions options;
  options.rate_wpm = 150;
  options.variant = "m3";
  EspeakPhonemeSource source(options);
  const SpeechLine line = source.Synthesize(kSentence, "en-us");
  fs::create_directories(folder);
  const fs::path path = folder / "recording.wav";
  test::WriteWav(path, FloatToPcm(ResampleAudio(PcmToFloat(line.audio), line.sample_rate, 44100)), 44100);
  return path;
}

PlayerOptions Headless(const fs::path& out) {
  PlayerOptions options;
  options.headless = true;
  fs::create_directories(out);  // outputs' folders must exist
  options.frames_dir = out / "frames";
  options.wav = out / "speech.wav";
  options.fps = 20.0;
  options.width = 96;
  options.height = 72;
  options.msaa = 0;
  options.still = true;
  return options;
}

TEST_CASE("Player options: --audio takes --text or --track", "[demo][recorded]") {
  const PlayerOptions aligned = ParseOptions({"--audio", "a.wav", "--text", "hello", "--voice", "de"});
  CHECK(aligned.audio == "a.wav");
  CHECK(aligned.text == "hello");
  CHECK(player::WantsRecordedSpeech(aligned));
  CHECK(ParseOptions({"--track", "t.json"}).track == "t.json");
  CHECK_FALSE(player::WantsRecordedSpeech(ParseOptions({"--say", "hi"})));
  CHECK_FALSE(player::WantsRoughMode(aligned));
  CHECK_FALSE(player::WantsRoughMode(ParseOptions({"--track", "t.json", "--audio", "a.wav"})));
  // --audio alone: the rough mode.
  const PlayerOptions rough = ParseOptions({"--audio", "a.wav"});
  CHECK(player::WantsRecordedSpeech(rough));
  CHECK(player::WantsRoughMode(rough));
  CHECK_THROWS_AS(ParseOptions({"--text", "hello"}), UsageError);
  CHECK_THROWS_AS(ParseOptions({"--audio", "a.wav", "--text", "x", "--say", "y"}), UsageError);
  CHECK_THROWS_AS(ParseOptions({"--audio", "a.wav", "--text", "x", "--track", "t.json"}), UsageError);
}

TEST_CASE("Player: headless --audio --text plays the recording, mouth on its speech", "[demo][recorded]") {
  const fs::path out = fs::path(FACERIG_TEST_OUTPUT_DIR) / "player_recorded";
  fs::remove_all(out);
  const fs::path wav = RecordingWav(out);
  const AudioClip recording = ReadAudioFile(wav);
  const Rig rig = LoadRigOrTemplateFolder(FACERIG_DEFAULT_HEAD);
  PlayerOptions options = Headless(out);
  options.audio = wav;
  options.text = kSentence;
  std::ostringstream log;
  const player::HeadlessResult result = player::RunHeadless(rig, options, log);
  INFO(log.str());

  // The WAV: the lead-in's silence, then the recording at its own rate.
  const AudioClip written_clip = ReadAudioFile(options.wav);
  const int rate = written_clip.sample_rate;
  const std::vector<std::int16_t> written = FloatToPcm(written_clip.samples);  // exact for 16-bit PCM
  CHECK(rate == 44100);
  const auto lead_in = static_cast<std::size_t>(std::lround(result.speech_start * rate));
  REQUIRE(written.size() == lead_in + recording.samples.size());
  CHECK(std::equal(written.begin() + static_cast<std::ptrdiff_t>(lead_in), written.end(),
                   FloatToPcm(recording.samples).begin()));

  // The phonemes lie on the recording, and the lips are open where /a/ of "map" sounds, closed at its /m/.
  const std::vector<Phoneme>& phonemes = result.speech.phonemes;
  REQUIRE(phonemes.size() > 8);
  CHECK(phonemes.back().start.count() <= recording.duration_seconds() + 1e-6);
  const auto frame_at = [&](double audio_seconds) {
    return static_cast<std::size_t>(std::lround((audio_seconds + result.speech_start) * options.fps));
  };
  const auto last_m = std::find_if(phonemes.rbegin(), phonemes.rend(), [](const Phoneme& p) { return p.symbol.view() == "m"; });
  REQUIRE(last_m != phonemes.rend());
  const Phoneme& vowel = *(last_m.base());  // the vowel after the /m/ of "map"
  const double open = result.lip_aperture[frame_at(vowel.start.count() + 0.5 * vowel.duration.count())];
  const double closed = result.lip_aperture[frame_at(last_m->start.count() + 0.5 * last_m->duration.count())];
  INFO("aperture at the vowel " << open << ", at /m/ " << closed);
  CHECK(open > closed);
  CHECK(open > 0.0);

  // The same through a track naming the recording: the same phonemes.
  const fs::path track = out / "track.json";
  WritePhonemeTrack(track, result.speech, "recording.wav");
  PlayerOptions from_track = Headless(out / "from_track");
  from_track.track = track;
  const player::HeadlessResult again = player::RunHeadless(rig, from_track, log);
  REQUIRE(again.speech.phonemes.size() == phonemes.size());
  CHECK(again.speech.phonemes.back().start.count() == Approx(phonemes.back().start.count()).margin(1e-6));
  CHECK(again.speech.audio == result.speech.audio);
}

TEST_CASE("Player: headless --audio alone speaks in the rough mode, mouth open on the loud vowels", "[demo][recorded]") {
  const fs::path out = fs::path(FACERIG_TEST_OUTPUT_DIR) / "player_rough";
  fs::remove_all(out);
  const fs::path wav = RecordingWav(out);
  const AudioClip recording = ReadAudioFile(wav);
  const Rig rig = LoadRigOrTemplateFolder(FACERIG_DEFAULT_HEAD);
  PlayerOptions options = Headless(out);
  options.audio = wav;
  std::ostringstream log;
  const player::HeadlessResult result = player::RunHeadless(rig, options, log);
  INFO(log.str());
  CHECK(result.speech.text.empty());
  CHECK(result.speech.sample_rate == 44100);
  CHECK(result.speech.audio == FloatToPcm(recording.samples));
  // Rough shapes on the recording's timeline; the lips open on an open vowel, rest before speech.
  const std::vector<Phoneme>& phonemes = result.speech.phonemes;
  REQUIRE(phonemes.size() >= 4);
  CHECK(phonemes.back().start.count() <= recording.duration_seconds() + 1e-6);
  const auto open_vowel = std::find_if(phonemes.begin(), phonemes.end(), [](const Phoneme& p) {
    return p.symbol.view() == "a" && p.duration.count() >= 0.06;
  });
  REQUIRE(open_vowel != phonemes.end());
  const auto frame_at = [&](double audio_seconds) {
    return static_cast<std::size_t>(std::lround((audio_seconds + result.speech_start) * options.fps));
  };
  const double open = result.lip_aperture[frame_at(open_vowel->start.count() + 0.5 * open_vowel->duration.count())];
  const double rest = result.lip_aperture[frame_at(-0.5 * result.speech_start)];
  INFO("aperture at the open vowel " << open << ", in the lead-in " << rest);
  CHECK(open > rest);
}

TEST_CASE("Player: a bad recording is an error naming it, and nothing is written", "[demo][recorded]") {
  const fs::path out = fs::path(FACERIG_TEST_OUTPUT_DIR) / "player_recorded_bad";
  fs::remove_all(out);
  fs::create_directories(out);
  const fs::path bad = out / "bad.wav";
  test::WriteWav(bad, std::vector<std::int16_t>{}, 22050);
  const Rig rig = LoadRigOrTemplateFolder(FACERIG_DEFAULT_HEAD);
  PlayerOptions options = Headless(out);
  options.audio = bad;
  options.text = kSentence;
  std::ostringstream log;
  try {
    player::RunHeadless(rig, options, log);
    FAIL("no error");
  } catch (const IoError& e) {
    CHECK_THAT(e.what(), Catch::Matchers::Contains(bad.string()));
  }
  CHECK_FALSE(fs::exists(options.wav));
  CHECK_FALSE(fs::exists(options.frames_dir));
  // A track that names no audio, without --audio.
  const fs::path track = out / "silent_track.json";
  SpeechLine line;
  line.text = "a";
  line.phonemes.push_back(Phoneme{});
  line.phonemes.back().symbol.assign("a");
  WritePhonemeTrack(track, line);
  options.audio.clear();
  options.text.clear();
  options.track = track;
  CHECK_THROWS_WITH(player::RunHeadless(rig, options, log), Catch::Matchers::Contains("names no audio"));
  // A track naming audio outside its folder: refused, pointing to --audio.
  WritePhonemeTrack(track, line, "../elsewhere.wav");
  CHECK_THROWS_WITH(player::RunHeadless(rig, options, log), Catch::Matchers::Contains("--audio"));
  CHECK_FALSE(fs::exists(options.frames_dir));
}

}  // namespace
}  // namespace facerig
