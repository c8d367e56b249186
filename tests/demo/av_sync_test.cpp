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
#include "facerig/offline/recording_alignment.h"
#include "facerig/runtime/io/audio_file.h"
#include "facerig/runtime/speech/phoneme_track_file.h"
#include "facerig/runtime/speech/phoneme_visemes.h"
#include "headless_player.h"
#include "media_writer.h"
#include "player_options.h"
#include "support/av_sync.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

const fs::path kRecording =
    "/usr/share/pocketsphinx/test/data/librivox/sense_and_sensibility_01_austen_64kb-0880.wav";
constexpr const char* kTranscript = "he was not an ill disposed young man";
constexpr double kStep = 0.001;  // the lag's resolution

struct Render {
  double fps = 100.0;
  int width = 160, height = 120;
};

struct PlayerRun {
  double fps = 0.0;
  player::HeadlessResult result;
  std::vector<double> mouth;  // per frame: mean RGB difference from frame 0 in the mouth box
  AudioClip wav;              // the WAV as written (it starts at frame 0)
};

// Mean absolute RGB difference (0..255) of `frame` from `first` in the box.
double BoxDifference(const player::Image& frame, const player::Image& first, int x0, int y0, int x1, int y1) {
  double sum = 0.0;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      for (int c = 0; c < 3; ++c) {
        const std::size_t i = (static_cast<std::size_t>(y) * frame.width + x) * 4 + c;
        sum += std::abs(static_cast<int>(frame.rgba[i]) - static_cast<int>(first.rgba[i]));
      }
    }
  }
  return sum / (3.0 * (x1 - x0) * (y1 - y0));
}

// The player speaking the recording with `track`; the mouth series from its PNGs.
PlayerRun RunPlayer(const Rig& rig, const fs::path& track, const fs::path& out, const Render& render) {
  player::PlayerOptions options;
  options.headless = true;
  options.track = track;
  options.audio = kRecording;
  options.frames_dir = out / "frames";
  options.wav = out / "player.wav";
  options.fps = render.fps;
  options.width = render.width;
  options.height = render.height;
  options.still = true;  // only speech and blinks move; the box holds only the mouth
  std::ostringstream log;
  PlayerRun run{render.fps, player::RunHeadless(rig, options, log), {}, ReadAudioFile(options.wav)};
  REQUIRE(run.result.has_mouth);
  const int r = std::max(4, static_cast<int>(std::ceil(run.result.mouth_radius_pixels)));
  const int cx = static_cast<int>(run.result.mouth_pixel.x), cy = static_cast<int>(run.result.mouth_pixel.y);
  const int x0 = std::max(0, cx - r), x1 = std::min(options.width, cx + r);
  const int y0 = std::max(0, cy - r / 2), y1 = std::min(options.height, cy + r);
  const player::Image first = player::ReadPng(run.result.frames.front());
  for (const fs::path& frame : run.result.frames) {
    run.mouth.push_back(BoxDifference(player::ReadPng(frame), first, x0, y0, x1, y1));
  }
  return run;
}

test::LagPeak MeasureLag(const PlayerRun& run) {
  const std::vector<double> sound = test::RmsEnvelope(run.wav.samples, run.wav.sample_rate, kStep, 1.0 / run.fps);
  const std::vector<double> mouth = test::Interpolate(run.mouth, 1.0 / run.fps, kStep);
  return test::PeakLag(sound, mouth, kStep, 0.150);
}

bool IsVowel(const Phoneme& p) {
  const auto visemes = LookupPhonemeVisemes("en-us", p.symbol.view());
  if (!visemes || visemes->count == 0) return false;
  const Viseme v = visemes->visemes[0];
  return v == Viseme::kAA || v == Viseme::kE || v == Viseme::kIH || v == Viseme::kOH || v == Viseme::kOU;
}

bool IsBilabial(const Phoneme& p) {
  const auto visemes = LookupPhonemeVisemes("en-us", p.symbol.view());
  return visemes && visemes->count > 0 && visemes->visemes[0] == Viseme::kPP;
}

struct Closure {
  std::string symbol;
  double lips_closed = 0.0;        // WAV time (s) of the frame with the least mouth opening
  double acoustic = 0.0;           // centre of the quietest 30 ms
  double closed_from = 0.0, closed_to = 0.0;  // frames at most 15% of the way from rest to the widest
};

// Each /p b m/ in `phonemes` (recording time; the WAV holds them `offset` s
// later): searched between the preceding vowel's middle and the next
// vowel's onset, in the frames and in the WAV.
std::vector<Closure> MeasureClosures(const PlayerRun& run, const std::vector<Phoneme>& phonemes, double offset) {
  const double widest = *std::max_element(run.mouth.begin(), run.mouth.end());
  std::vector<Closure> closures;
  for (std::size_t i = 0; i < phonemes.size(); ++i) {
    if (!IsBilabial(phonemes[i])) continue;
    double from = phonemes[i].start.count() - 0.15, to = phonemes[i].start.count() + 0.15;
    for (std::size_t j = i; j-- > 0;) {
      if (IsVowel(phonemes[j])) { from = (phonemes[j].start + 0.5 * phonemes[j].duration).count(); break; }
    }
    for (std::size_t j = i + 1; j < phonemes.size(); ++j) {
      if (IsVowel(phonemes[j])) { to = phonemes[j].start.count(); break; }
    }
    from += offset, to += offset;
    Closure c{std::string(phonemes[i].symbol.view())};
    c.acoustic = test::QuietestWindow(run.wav.samples, run.wav.sample_rate, from, to - 0.03, 0.03) + 0.015;
    const auto first = static_cast<std::size_t>(std::max(0.0, std::floor(from * run.fps)));
    const auto last = std::min(run.mouth.size() - 1, static_cast<std::size_t>(std::ceil(to * run.fps)));
    std::size_t least = first;
    for (std::size_t f = first; f <= last; ++f) least = run.mouth[f] < run.mouth[least] ? f : least;
    c.lips_closed = static_cast<double>(least) / run.fps;
    std::size_t a = least, b = least;
    while (a > first && run.mouth[a - 1] <= 0.15 * widest) --a;
    while (b < last && run.mouth[b + 1] <= 0.15 * widest) ++b;
    c.closed_from = static_cast<double>(a) / run.fps - 0.5 / run.fps;
    c.closed_to = static_cast<double>(b) / run.fps + 0.5 / run.fps;
    closures.push_back(c);
  }
  return closures;
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
  for (const Closure& c : MeasureClosures(run, aligned.phonemes, offset)) {
    const double q0 = c.acoustic - 0.015, q1 = c.acoustic + 0.015;
    std::printf("  /%s/ lips least open at %.3f s, closed %.3f-%.3f s; quietest 30 ms centred %.3f s: %+.0f ms, %s\n",
                c.symbol.c_str(), c.lips_closed, c.closed_from, c.closed_to, c.acoustic,
                1000 * (c.lips_closed - c.acoustic), c.closed_from < q1 && q0 < c.closed_to ? "overlap" : "apart");
  }
  CHECK(std::abs(lag.lag_seconds) <= 0.020);
  CHECK(late_lag.lag_seconds - lag.lag_seconds == Approx(0.050).margin(0.015));
}

}  // namespace
}  // namespace facerig
