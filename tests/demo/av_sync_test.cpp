// The player on a real recording (pocketsphinx-testdata's librivox) and its
// transcript, headless: whether the mouth in the frames moves with the sound
// in the WAV, measured from the pixels and the WAV only (the frames' and the
// WAV's own time: frame i at i / fps, sample j at j / rate).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/offline/io/template_folder.h"
#include "facerig/offline/speech/recording_alignment.h"
#include "facerig/runtime/io/audio_file.h"
#include "facerig/runtime/io/phoneme_track_file.h"
#include "headless_player.h"
#include "media_writer.h"
#include "player_options.h"
#include "measure/av_sync.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

const fs::path kRecording =
    "/usr/share/pocketsphinx/test/data/librivox/sense_and_sensibility_01_austen_64kb-0880.wav";
constexpr const char* kTranscript = "he was not an ill disposed young man";

struct Render {
  double fps = 100.0;
  int width = 160, height = 120;
};

struct PlayerRun {
  double fps = 0.0;
  player::HeadlessResult result;
  std::vector<double> mouth;  // per frame, from the PNGs (test::MouthSeries)
  AudioClip wav;              // the WAV as written (it starts at frame 0)
};

test::FramePixels Pixels(player::Image image) {
  return {image.width, image.height, 4, std::move(image.rgba)};
}

// The player speaking the recording with `track`; the mouth series from its PNGs.
PlayerRun RunPlayer(const Rig& rig, const fs::path& track, const fs::path& out, const Render& render) {
  player::PlayerOptions options;
  options.headless = true;
  options.track = track;
  options.audio = kRecording;
  fs::create_directories(out);  // outputs' folders must exist
  options.frames_dir = out / "frames";
  options.wav = out / "player.wav";
  options.fps = render.fps;
  options.width = render.width;
  options.height = render.height;
  options.still = true;  // only speech and blinks move the face
  std::ostringstream log;
  PlayerRun run{render.fps, player::RunHeadless(rig, options, log), {}, ReadAudioFile(options.wav)};
  std::vector<test::FramePixels> frames;
  for (const fs::path& frame : run.result.frames) frames.push_back(Pixels(player::ReadPng(frame)));
  const test::PixelBox box = test::ChangingLowerBox(frames);
  REQUIRE(box.x1 > box.x0);
  run.mouth = test::MouthSeries(frames, box);
  return run;
}

test::LagPeak MeasureLag(const PlayerRun& run) {
  return test::MouthLag(run.mouth, run.fps, run.wav.samples, run.wav.sample_rate);
}

SpeechLine Shifted(SpeechLine line, double seconds) {
  for (Phoneme& p : line.phonemes) p.start += Seconds(seconds);
  return line;
}

// The recording's track as aligned, and the same 50 ms late, in `out`.
SpeechLine AlignedTrack(const fs::path& out) {
  INFO("needs Debian pocketsphinx-testdata (scripts/install-deps.sh): " << kRecording);
  REQUIRE(fs::exists(kRecording));
  fs::remove_all(out);
  fs::create_directories(out);
  EspeakPhonemeSource source;
  const SpeechLine aligned = AlignRecording(source, ReadAudioFile(kRecording), kTranscript, "en-us").alignment.line;
  WritePhonemeTrack(out / "track.json", aligned);
  WritePhonemeTrack(out / "track_50ms_late.json", Shifted(aligned, 0.050));
  return aligned;
}

TEST_CASE("Player on a real recording: the mouth in the frames within 20 ms of the sound in the WAV",
          "[demo][recorded][av-sync]") {
  const fs::path out = fs::path(FACERIG_TEST_OUTPUT_DIR) / "av_sync";
  AlignedTrack(out);
  const Rig rig = LoadRigOrTemplateFolder(FACERIG_DEFAULT_HEAD);
  const PlayerRun run = RunPlayer(rig, out / "track.json", out / "aligned", Render{50.0, 128, 96});
  const test::LagPeak lag = MeasureLag(run);
  INFO("mouth vs sound lag " << 1000 * lag.lag_seconds << " ms, r " << lag.correlation);
  CHECK(std::abs(lag.lag_seconds) <= 0.020);
  CHECK(lag.correlation > 0.3);
}

TEST_CASE("Player on a real recording: lag at 100 fps, a 50 ms late track, /p b m/ closures in frames and WAV",
          "[demo][recorded][.measure]") {
  const fs::path out = fs::path(FACERIG_TEST_OUTPUT_DIR) / "av_sync_measure";
  const SpeechLine aligned = AlignedTrack(out);
  const Rig rig = LoadRigOrTemplateFolder(FACERIG_DEFAULT_HEAD);
  const PlayerRun run = RunPlayer(rig, out / "track.json", out / "aligned", Render{});
  const PlayerRun late = RunPlayer(rig, out / "track_50ms_late.json", out / "late", Render{});
  const test::LagPeak lag = MeasureLag(run), late_lag = MeasureLag(late);
  std::printf("av-sync %s: mouth vs sound lag %+.0f ms (r %.2f); track 50 ms late: %+.0f ms (r %.2f)\n",
              kRecording.filename().c_str(), 1000 * lag.lag_seconds, lag.correlation, 1000 * late_lag.lag_seconds,
              late_lag.correlation);
  const double offset = run.result.speech_start;  // the WAV starts at frame 0: the lead-in is in both
  for (const test::BilabialClosure& c : test::MeasureBilabialClosures(run.mouth, run.fps, run.wav.samples,
                                                                     run.wav.sample_rate, aligned.phonemes, offset)) {
    std::printf("  /%s/ lips least open at %.3f s, closed %.3f-%.3f s; quietest 30 ms %.3f-%.3f s: %s\n",
                c.symbol.c_str(), c.lips_least_open, c.lips_from, c.lips_to, c.acoustic_from, c.acoustic_to,
                c.overlaps() ? "overlap" : "apart");
  }
  CHECK(std::abs(lag.lag_seconds) <= 0.020);
  CHECK(late_lag.lag_seconds - lag.lag_seconds == Approx(0.050).margin(0.015));
}

}  // namespace
}  // namespace facerig
