#include "player_options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <system_error>

#include <CLI/CLI.hpp>

namespace facerig::player {
namespace {

double ParseNumber(const std::string& flag, const std::string& text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
    throw UsageError(flag + ": not a number: '" + text + "'");
  }
  return value;
}

}  // namespace

std::string UsageText() {
  return R"(facerig-player: type text, the face speaks (SDL2 + OpenGL 3.3; espeak-ng, GPL-3)

usage: facerig-player [--rig FILE] [--say TEXT] [--voice V] [--emotion NAME[:I]]... [--still]
                      [--timing FILE.json]
       facerig-player --audio FILE [--text TEXT [--voice V]] ... | --track FILE.json [--audio FILE] ...
       facerig-player [--quit-after S] [--screenshot FILE.png]
       facerig-player --headless --frames DIR [--wav FILE] [--mp4 FILE] [--fps 30]
                      [--size WxH] [--duration S] [--lead-in S] [--yaw D] [--say TEXT] [--hud] ...
       facerig-player --version

  --rig FILE       .glb, .gltf, .frig or an OBJ template folder
                   (default: the built-in head installed with the player in
                   ../share/facerig/, or the build's, else ../shared/data/ict-facekit)
  --say TEXT       speak TEXT at start
  --voice V        espeak-ng voice / language (default en-us)
  --audio FILE     speak a recording (WAV, FLAC, Ogg, ...) instead of synthesized text, with
                   --text TEXT, its transcript (aligned at start; --voice: its language), or
                   --track FILE.json, its phoneme track (e.g. from `facerig align`; the
                   track's "audio" is used when --audio is not given), or alone: the rough
                   mode, a coarse mouth from loudness and spectrum (no phonemes; p, b, m
                   do not close the lips)
  --emotion E[:I]  joy, sadness, fear, anger, surprise or disgust at intensity I (default 0.7)
  --still          no idle head motion or eye saccades (blinks stay)
  --msaa N         anti-aliasing samples: 0, 2, 4 (default) or 8
  --yaw D          start with the camera turned D degrees about the head (positive: towards
                   the face's left; -180..180); --pitch D: from above (-80..80)
  --timing FILE    write per-frame CPU timing (update, blend, normals, upload, draw) as JSON
  --quit-after S   window: quit after S seconds; --screenshot FILE saves the last frame (PNG)
  --headless       no window and no sound card: render offscreen (EGL), animation time =
                   frame / fps; writes DIR/frame_00000.png ... and the speech as a WAV
  --lead-in S      headless: the speech starts S seconds after frame 0 (default 0.3), so the
                   first frame is the face at rest; the WAV starts with frame 0 (S seconds of
                   silence, then the speech), so frames and WAV mux in sync
  --hud            headless: draw the HUD into the frames
  --version        print the version and exit

exit codes: 0 ok, 1 failure, 2 bad command line, 130 / 143 headless run stopped by
SIGINT / SIGTERM. Headless outputs are written as one set: a failed or stopped run
leaves the previous frames, WAV, MP4 and timing JSON as they were.

window keys: type a line and press Enter to speak it (Up/Down: history); with an empty line:
  1-6 toggle joy, sadness, fear, anger, surprise, disgust; +/- intensity; space pause;
  Esc quit. Drag to orbit, scroll to zoom, Tab resets the camera. --size WxH sizes the window.
)";
}

namespace {

// --emotion NAME[:I] appended to `emotions`.
void AddEmotion(const std::string& text, std::vector<std::pair<Emotion, float>>& emotions) {
  const std::size_t colon = text.find(':');
  const std::optional<Emotion> emotion = ParseEmotion(text.substr(0, colon));
  if (!emotion) {
    throw UsageError("--emotion: unknown emotion '" + text.substr(0, colon) +
                     "' (joy, sadness, fear, anger, surprise, disgust)");
  }
  const double intensity = colon == std::string::npos ? 0.7 : ParseNumber("--emotion", text.substr(colon + 1));
  emotions.emplace_back(*emotion, static_cast<float>(std::clamp(intensity, 0.0, 1.0)));
}

// --size WxH into width and height.
void SetSize(const std::string& text, PlayerOptions& options) {
  const std::size_t x = text.find('x');
  if (x == std::string::npos) throw UsageError("--size: expected WxH, got '" + text + "'");
  const double w = ParseNumber("--size", text.substr(0, x)), h = ParseNumber("--size", text.substr(x + 1));
  if (w < 16 || h < 16 || w > 8192 || h > 8192 || w != std::floor(w) || h != std::floor(h)) {
    throw UsageError("--size: width and height must be whole numbers in [16, 8192]");
  }
  options.width = static_cast<int>(w);
  options.height = static_cast<int>(h);
}

void AddPlayerOptions(CLI::App& app, PlayerOptions& options, std::vector<std::string>& emotions, std::string& size) {
  app.set_help_flag();  // -h/--help set options.help: main prints UsageText()
  app.add_flag("-h,--help", options.help);
  app.add_flag("--version", options.version);
  app.add_option("--rig", options.rig);
  app.add_option("--say", options.say);
  app.add_option("--voice", options.voice);
  app.add_option("--audio", options.audio);
  app.add_option("--text", options.text);
  app.add_option("--track", options.track);
  app.add_option("--emotion", emotions)->expected(1)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app.add_flag("--still", options.still);
  app.add_flag("--hud", options.hud);
  app.add_option("--timing", options.timing_json);
  app.add_flag("--headless", options.headless);
  app.add_option("--frames", options.frames_dir);
  app.add_option("--wav", options.wav);
  app.add_option("--mp4", options.mp4);
  app.add_option("--fps", options.fps)->check(CLI::Range(1e-9, 1000.0));
  app.add_option("--duration", options.duration)->check(CLI::Range(1e-9, 3600.0));
  app.add_option("--msaa", options.msaa)->check(CLI::IsMember({0, 2, 4, 8}));
  app.add_option("--yaw", options.yaw_degrees)->check(CLI::Range(-180.0f, 180.0f));
  app.add_option("--pitch", options.pitch_degrees)->check(CLI::Range(-80.0f, 80.0f));
  app.add_option("--quit-after", options.quit_after)->check(CLI::NonNegativeNumber);
  app.add_option("--screenshot", options.screenshot);
  app.add_option("--lead-in", options.lead_in)->check(CLI::Range(0.0, 60.0));
  app.add_option("--size", size);
}

// --audio, --text and --track: a recording with its transcript, its track, or
// alone (the rough mode).
void CheckRecordingOptions(const PlayerOptions& options) {
  const bool recording = !options.audio.empty() || !options.track.empty();
  if (recording && !options.say.empty()) throw UsageError("--say speaks synthesized text: not with --audio or --track");
  if (!options.text.empty() && options.audio.empty()) throw UsageError("--text is the transcript of --audio FILE");
  if (!options.text.empty() && !options.track.empty()) throw UsageError("--text and --track: give one of them");
}

}  // namespace

PlayerOptions ParseOptions(const std::vector<std::string>& args) {
  PlayerOptions options;
  std::vector<std::string> emotions;
  std::string size;
  CLI::App app("facerig-player", "facerig-player");
  AddPlayerOptions(app, options, emotions, size);
  try {
    app.parse(std::vector<std::string>(args.rbegin(), args.rend()));  // CLI11 takes them reversed
  } catch (const CLI::ParseError& error) {
    throw UsageError(error.what());
  }
  for (const std::string& emotion : emotions) AddEmotion(emotion, options.emotions);
  if (!size.empty()) SetSize(size, options);
  if (options.duration && !std::isfinite(*options.duration)) throw UsageError("--duration: not a number");
  if (!std::isfinite(options.fps) || !std::isfinite(options.lead_in) || !std::isfinite(options.quit_after)) {
    throw UsageError("--fps, --lead-in and --quit-after must be finite numbers");
  }
  if (options.headless && options.frames_dir.empty() && !options.help) {
    throw UsageError("--headless needs --frames DIR");
  }
  CheckRecordingOptions(options);
  if (!options.headless && (!options.frames_dir.empty() || !options.wav.empty() || !options.mp4.empty())) {
    throw UsageError("--frames, --wav and --mp4 need --headless");
  }
  return options;
}

std::filesystem::path DefaultRigPath(const std::filesystem::path& executable) {
  std::error_code error;
  if (!executable.empty()) {
    const std::filesystem::path installed =
        (executable.parent_path() / FACERIG_INSTALLED_HEAD_FROM_BINDIR).lexically_normal();
    if (std::filesystem::exists(installed, error)) return installed;
  }
  const std::filesystem::path build_tree_head = FACERIG_DEFAULT_HEAD;
  if (std::filesystem::exists(build_tree_head, error)) return build_tree_head;
  return std::filesystem::path(FACERIG_SHARED_DATA_DIR) / "ict-facekit";
}

std::filesystem::path DefaultRigPath() {
  std::error_code error;
  // Linux: the running executable, wherever it was installed or copied.
  const std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe", error);
  return DefaultRigPath(error ? std::filesystem::path() : executable);
}

std::filesystem::path RigPath(const PlayerOptions& options) {
  return options.rig.empty() ? DefaultRigPath() : options.rig;
}

}  // namespace facerig::player
