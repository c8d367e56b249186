#include "bench/av_sync.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/common.h"
#include "bench/json.h"
#include "bench/recordings.h"
#include "facerig/espeak/espeak_phoneme_source.h"
#include "facerig/offline/default_head/default_head.h"
#include "facerig/offline/speech/recording_alignment.h"
#include "facerig/runtime/io/audio_file.h"
#include "facerig/runtime/files/image_file.h"
#include "facerig/runtime/files/input_file.h"
#include "facerig/runtime/io/phoneme_track_file.h"
#include "measure/av_sync.h"

namespace {

namespace fs = std::filesystem;

struct AvSyncOptions {
  std::string recordings_dir = "/usr/share/pocketsphinx/test/data/librivox";
  std::string player = FACERIG_BENCH_PLAYER;
  std::string work_dir = (fs::temp_directory_path() / "facerig-bench-av-sync").string();
  double fps = 100.0;
  int width = 160, height = 120;
  double late_seconds = 0.050;
  std::string json_path;
};

constexpr double kLeadIn = 0.3;  // passed to the player: speech starts this long after frame 0

void AddAvSyncOptions(CLI::App& app, AvSyncOptions& o) {
  app.add_option("--recordings", o.recordings_dir,
                 "folder with a pocketsphinx 'transcription' file beside ID.wav (default: pocketsphinx-testdata's "
                 "librivox)");
  app.add_option("--player", o.player, "the facerig-player executable (default: the one built with this bench)");
  app.add_option("--work", o.work_dir, "folder for frames, WAVs and MP4s (replaced per recording)");
  app.add_option("--fps", o.fps, "frames per second of the render and the mux (default 100)")
      ->check(facerig::cli::InRange(1, 1000));
  app.add_option("--width", o.width, "frame width (default 160)")->check(facerig::cli::InRange(16, 8192));
  app.add_option("--height", o.height, "frame height (default 120)")->check(facerig::cli::InRange(16, 8192));
  app.add_option("--late", o.late_seconds, "the control track's delay in seconds (default 0.050)")
      ->check(facerig::cli::InRange(0.0, 1.0));
  app.add_option("--json", o.json_path, "write the results as JSON");
}

// Runs `command` through the shell, its output appended to `log`.
void Run(const std::string& command, const fs::path& log) {
  if (std::system(("{ " + command + "; } >>" + ShellQuote(log) + " 2>&1").c_str()) != 0) {
    throw std::runtime_error("failed (see " + log.string() + "): " + command);
  }
}

std::vector<facerig::test::FramePixels> ReadFrames(const fs::path& folder) {
  std::vector<fs::path> paths;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() == ".png") paths.push_back(entry.path());
  }
  std::sort(paths.begin(), paths.end());
  std::vector<facerig::test::FramePixels> frames;
  for (const fs::path& path : paths) {
    facerig::RgbImage image = facerig::DecodeImage(facerig::ReadImageFile(path));
    frames.push_back({image.width, image.height, 3, std::move(image.pixels)});
  }
  return frames;
}

struct Measured {
  std::vector<double> mouth;
  facerig::AudioClip audio;
  facerig::test::LagPeak lag;
};

Measured Measure(const fs::path& frames_dir, const fs::path& wav, double fps) {
  const std::vector<facerig::test::FramePixels> frames = ReadFrames(frames_dir);
  const facerig::test::PixelBox box = facerig::test::ChangingLowerBox(frames);
  if (box.x1 <= box.x0) throw std::runtime_error(frames_dir.string() + ": the mouth never moves");
  Measured m{facerig::test::MouthSeries(frames, box), facerig::ReadAudioFile(wav), {}};
  m.lag = facerig::test::MouthLag(m.mouth, fps, m.audio.samples, m.audio.sample_rate);
  return m;
}

// ffprobe's start time and duration of each stream of `mp4`.
nlohmann::json Probe(const fs::path& mp4, const fs::path& folder) {
  const fs::path out = folder / "probe.csv";
  Run("ffprobe -v error -show_entries stream=codec_type,start_time,duration -of csv=p=0 " + ShellQuote(mp4) + " >" +
          ShellQuote(out),
      folder / "log.txt");
  nlohmann::json streams = nlohmann::json::object();
  std::istringstream in(facerig::ReadInputText(out, 1 << 16));
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    std::string type, start, duration;
    std::getline(fields, type, ',');
    std::getline(fields, start, ',');
    std::getline(fields, duration, ',');
    streams[type] = {{"start_time", std::stod(start)}, {"duration", std::stod(duration)}};
  }
  return streams;
}

struct PlayerOutput {
  Measured png_wav, mp4;
  nlohmann::json streams;
};

// The player on `track` in `folder`: frames + WAV, the plain ffmpeg mux, the
// MP4 decoded back into frames and a WAV; both measured.
PlayerOutput PlayAndMux(const AvSyncOptions& o, const BenchRecording& r, const fs::path& track, const fs::path& folder) {
  fs::create_directories(folder / "decoded");
  const fs::path log = folder / "log.txt";
  const std::string fps = std::to_string(o.fps);
  Run(ShellQuote(o.player) + " --headless --still --track " + ShellQuote(track) + " --audio " + ShellQuote(r.wav) +
          " --frames " + ShellQuote(folder / "frames") + " --wav " + ShellQuote(folder / "player.wav") + " --fps " + fps +
          " --size " + std::to_string(o.width) + "x" + std::to_string(o.height) + " --lead-in " + std::to_string(kLeadIn),
      log);
  Run("cd " + ShellQuote(folder / "frames") + " && ffmpeg -loglevel error -y -framerate " + fps +
          " -i frame_%05d.png -i ../player.wav -c:v libx264 -pix_fmt yuv420p -c:a aac ../out.mp4",
      log);
  Run("ffmpeg -loglevel error -y -i " + ShellQuote(folder / "out.mp4") + " " +
          ShellQuote(folder / "decoded" / "f_%05d.png") + " -vn " + ShellQuote(folder / "decoded.wav"),
      log);
  return {Measure(folder / "frames", folder / "player.wav", o.fps),
          Measure(folder / "decoded", folder / "decoded.wav", o.fps), Probe(folder / "out.mp4", folder)};
}

facerig::SpeechLine Delayed(facerig::SpeechLine line, double seconds) {
  for (facerig::Phoneme& p : line.phonemes) p.start += facerig::Seconds(seconds);
  return line;
}

struct RecordingResult {
  nlohmann::json json;
  std::size_t bilabials = 0, overlapping = 0;
  std::vector<double> lags, mp4_lags, late_lags;
};

RecordingResult MeasureRecording(const AvSyncOptions& o, const BenchRecording& r, facerig::PhonemeSource& source) {
  const fs::path folder = fs::path(o.work_dir) / r.id;
  fs::remove_all(folder);
  fs::create_directories(folder);
  const facerig::AudioClip clip = facerig::ReadAudioFile(r.wav);
  const facerig::RecordingAlignment aligned = facerig::AlignRecording(source, clip, r.text, "en-us");
  facerig::WritePhonemeTrack(folder / "track.json", aligned.alignment.line);
  facerig::WritePhonemeTrack(folder / "track_late.json", Delayed(aligned.alignment.line, o.late_seconds));
  const PlayerOutput on_time = PlayAndMux(o, r, folder / "track.json", folder / "aligned");
  const PlayerOutput late = PlayAndMux(o, r, folder / "track_late.json", folder / "late");

  RecordingResult result;
  const auto& m = on_time.png_wav;
  nlohmann::json closures = nlohmann::json::array();
  for (const auto& c : facerig::test::MeasureBilabialClosures(m.mouth, o.fps, m.audio.samples, m.audio.sample_rate,
                                                               aligned.alignment.line.phonemes, kLeadIn)) {
    ++result.bilabials;
    result.overlapping += c.overlaps();
    closures.push_back({{"phoneme", c.symbol}, {"lips_closed_from", c.lips_from}, {"lips_closed_to", c.lips_to},
                        {"lips_least_open", c.lips_least_open}, {"quiet_from", c.acoustic_from},
                        {"quiet_to", c.acoustic_to}, {"overlap", c.overlaps()}});
  }
  result.lags = {m.lag.lag_seconds};
  result.mp4_lags = {on_time.mp4.lag.lag_seconds};
  result.late_lags = {late.png_wav.lag.lag_seconds};
  result.json = {{"recording", r.wav.string()},     {"audio_seconds", clip.duration_seconds()},
                 {"lag_ms", 1000 * m.lag.lag_seconds}, {"correlation", m.lag.correlation},
                 {"mp4_lag_ms", 1000 * on_time.mp4.lag.lag_seconds},
                 {"late_track_lag_ms", 1000 * late.png_wav.lag.lag_seconds},
                 {"mp4_streams", on_time.streams},  {"bilabial_closures", closures}};
  return result;
}

void PrintRow(const BenchRecording& r, const RecordingResult& x) {
  const nlohmann::json& j = x.json;
  const nlohmann::json& s = j["mp4_streams"];
  std::printf("| %s | %.2f | %+.0f ms (r %.2f) | %+.0f ms | %+.0f ms | %zu / %zu | video %.3f + %.3f s, audio %.3f + %.3f s |\n",
              r.id.c_str(), j["audio_seconds"].get<double>(), j["lag_ms"].get<double>(), j["correlation"].get<double>(),
              j["mp4_lag_ms"].get<double>(), j["late_track_lag_ms"].get<double>(), x.overlapping, x.bilabials,
              s.value("/video/start_time"_json_pointer, -1.0), s.value("/video/duration"_json_pointer, -1.0),
              s.value("/audio/start_time"_json_pointer, -1.0), s.value("/audio/duration"_json_pointer, -1.0));
}

int RunAvSync(const AvSyncOptions& o) {
  try {
    facerig::EspeakPhonemeSource source;
    std::printf("av-sync: %s at %.0f fps, %dx%d; lag > 0: the mouth follows the sound; control: the track %.0f ms late\n\n",
                o.recordings_dir.c_str(), o.fps, o.width, o.height, 1000 * o.late_seconds);
    std::printf("| recording | audio s | lag, PNG + WAV | lag, MP4 decoded | lag, track late | /p b m/ lips over the quiet gap | ffprobe (start + duration) |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    RecordingResult all;
    nlohmann::json recordings = nlohmann::json::array();
    for (const BenchRecording& r : ReadTranscription(o.recordings_dir)) {
      const RecordingResult x = MeasureRecording(o, r, source);
      PrintRow(r, x);
      recordings.push_back(x.json);
      all.bilabials += x.bilabials, all.overlapping += x.overlapping;
      all.lags.insert(all.lags.end(), x.lags.begin(), x.lags.end());
      all.mp4_lags.insert(all.mp4_lags.end(), x.mp4_lags.begin(), x.mp4_lags.end());
      all.late_lags.insert(all.late_lags.end(), x.late_lags.begin(), x.late_lags.end());
    }
    if (recordings.empty()) throw std::runtime_error(o.recordings_dir + ": no recordings");
    const double median = UpperMedian(all.lags), mp4 = UpperMedian(all.mp4_lags), late = UpperMedian(all.late_lags);
    std::printf("\nmedian lag %+.0f ms (MP4 %+.0f ms; track %.0f ms late: %+.0f ms); /p b m/ lips closed over the "
                "quiet gap: %zu / %zu\n",
                1000 * median, 1000 * mp4, 1000 * o.late_seconds, 1000 * late, all.overlapping, all.bilabials);
    const nlohmann::json report = {{"fps", o.fps},
                                   {"size", {o.width, o.height}},
                                   {"late_seconds", o.late_seconds},
                                   {"median_lag_ms", 1000 * median},
                                   {"median_mp4_lag_ms", 1000 * mp4},
                                   {"median_late_track_lag_ms", 1000 * late},
                                   {"bilabials", all.bilabials},
                                   {"bilabials_overlapping", all.overlapping},
                                   {"recordings", recordings}};
    return WriteBenchJson(o.json_path, report);
  } catch (const std::exception& error) {
    return ReportBenchFailure(error);
  }
}

}  // namespace

int RunAvSyncBenchmark(int argc, char** argv) {
  return ParseAndRunBench<AvSyncOptions>(argc, argv, "the player on real recordings: mouth vs sound from pixels and WAV",
                                         "facerig-bench av-sync", AddAvSyncOptions, RunAvSync);
}
