#include "player_options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <system_error>

#include <CLI/CLI.hpp>

#include "cli/options.h"  // InRange

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

constexpr const char* kDescription = R"(facerig-player: type text, the face speaks (SDL2 + OpenGL 3.3; espeak-ng, GPL-3)

usage: facerig-player [--rig FILE] [--say TEXT] [--voice V] [--emotion NAME[:I]]... [--still]
                      [--timing FILE.json]
       facerig-player --audio FILE [--text TEXT [--voice V]] ... | --track FILE.json [--audio FILE] ...
       facerig-player [--quit-after S] [--screenshot FILE.png]
       facerig-player --headless --frames DIR [--wav FILE] [--mp4 FILE] [--fps 30]
                      [--size WxH] [--duration S] [--lead-in S] [--yaw D] [--say TEXT] [--hud] ...
       facerig-player --version)";

constexpr const char* kFooter = R"(exit codes: 0 ok, 1 failure, 2 bad command line, 130 / 143 headless run stopped by
SIGINT / SIGTERM. Headless outputs are written as one set: a failed or stopped run
leaves the previous frames, WAV, MP4 and timing JSON as they were. The WAV, MP4 and
timing JSON may go inside the frames folder (--frames out/ --wav out/speech.wav);
output folders must exist (only the frames folder itself is created).

window keys: type a line and press Enter to speak it (Up/Down: history); with an empty line:
  1-6 toggle joy, sadness, fear, anger, surprise, disgust; +/- intensity; space pause;
  Esc quit. Drag to orbit, scroll to zoom, Tab resets the camera. --size WxH sizes the window.)";

// --emotion NAME[:I] appended to `emotions`.
void AddEmotion(const std::string& text, std::vector<std::pair<Emotion, float>>& emotions) {
  const std::size_t colon = text.find(':');
  const std::optional<Emotion> emotion = ParseEmotion(text.substr(0, colon));
  if (!emotion) {
    throw UsageError("--emotion: unknown emotion '" + text.substr(0, colon) +
                     "' (joy, sadness, fear, anger, surprise, disgust)");
  }
  const double intensity = colon == std::string::npos ? 0.7 : ParseNumber("--emotion", text.substr(colon + 1));
  if (intensity < 0.0 || intensity > 1.0) {
    throw UsageError("--emotion: intensity " + text.substr(colon + 1) + " of '" + text + "' is outside [0, 1]");
  }
  emotions.emplace_back(*emotion, static_cast<float>(intensity));
}

// --size WxH into width and height.
void SetSize(const std::string& text, PlayerOptions& options) {
  const std::size_t x = text.find('x');
  if (x == std::string::npos) throw UsageError("--size: expected WxH, got '" + text + "'");
  const double w = ParseNumber("--size", text.substr(0, x)), h = ParseNumber("--size", text.substr(x + 1));
  if (w < 16 || h < 16 || w > 8192 || h > 8192 || w != std::floor(w) || h != std::floor(h)) {
    throw UsageError("--size: '" + text + "': width and height must be whole numbers in [16, 8192]");
  }
  options.width = static_cast<int>(w);
  options.height = static_cast<int>(h);
}

void AddHeadlessOptions(CLI::App& app, PlayerOptions& options) {
  const char* group = "Headless (no window, no sound card)";
  app.add_flag("--headless", options.headless,
               "render offscreen (EGL) at a fixed frame rate: animation time = frame / fps")
      ->group(group);
  app.add_option("--frames", options.frames_dir, "DIR: write DIR/frame_00000.png ... (needed by --headless)")
      ->group(group);
  app.add_option("--wav", options.wav, "FILE: write the speech as a WAV that starts with frame 0 (may be in DIR)")
      ->group(group);
  app.add_option("--mp4", options.mp4,
                 "FILE: also mux the frames and the speech into an MP4 (needs ffmpeg; may be in DIR; without\n"
                 "--wav the speech also goes into FILE's name with .wav)")
      ->group(group);
  app.add_option("--fps", options.fps, "N: frames per second (default 30; 0.1 to 1000)")
      ->check(facerig::cli::InRange(0.1, 1000.0))
      ->group(group);
  app.add_option("--duration", options.duration,
                 "S: seconds to render, 0.001 to 3600 (default: lead-in + speech + 0.6 s, at least 1 s)")
      ->check(facerig::cli::InRange(0.001, 3600.0))
      ->group(group);
  app.add_option("--lead-in", options.lead_in,
                 "S: the speech starts S seconds after frame 0 (default 0.3, up to 60), so the first frame is the\n"
                 "face at rest; the WAV holds those S seconds of silence, so frames and WAV mux in sync")
      ->check(facerig::cli::InRange(0.0, 60.0))
      ->group(group);
  app.add_flag("--hud", options.hud, "draw the HUD into the frames")->group(group);
}

// Every option with its description: --help is generated from these.
void AddPlayerOptions(CLI::App& app, PlayerOptions& options, std::vector<std::string>& emotions, std::string& size) {
  app.set_help_flag();  // -h/--help set options.help: main prints UsageText()
  app.add_flag("-h,--help", options.help, "print this help and exit");
  app.add_flag("--version", options.version, "print the version and exit");
  app.add_option("--rig", options.rig,
                 "FILE: .glb, .gltf, .frig or an OBJ template folder (default: the built-in head installed with the\n"
                 "player in ../share/facerig/, or the build's, else ../shared/data/ict-facekit)");
  app.add_option("--say", options.say, "TEXT: speak TEXT at start");
  app.add_option("--voice", options.voice, "V: espeak-ng voice / language (default en-us)");
  app.add_option("--audio", options.audio,
                 "FILE: speak a recording (WAV, FLAC, Ogg, ...) instead of synthesized text, with --text (its\n"
                 "transcript, aligned at start) or --track, or alone: the rough mode, a coarse mouth from loudness\n"
                 "and spectrum (no phonemes; p, b, m do not close the lips)");
  app.add_option("--text", options.text, "TEXT: the transcript of --audio (--voice: its language)");
  app.add_option("--track", options.track,
                 "FILE.json: a phoneme track (e.g. from `facerig align`); its \"audio\" is used without --audio");
  app.add_option("--emotion", emotions,
                 "E[:I]: joy, sadness, fear, anger, surprise or disgust at intensity I (default 0.7); repeatable")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app.add_flag("--still", options.still, "no idle head motion or eye saccades (blinks stay)");
  app.add_flag("--recomputed-normals", options.recomputed_normals,
               "recompute every normal from the triangles each frame instead of blending each shape's change of\n"
               "them (the same picture within a degree, several times the blend's cost)");
  app.add_option("--msaa", options.msaa, "N: anti-aliasing samples: 0, 2, 4 (default) or 8")
      ->check(CLI::IsMember({0, 2, 4, 8}));
  app.add_option("--yaw", options.yaw_degrees,
                 "D: start with the camera turned D degrees about the head (-180..180; positive: towards the\n"
                 "face's left)")
      ->check(facerig::cli::InRange(-180.0f, 180.0f));
  app.add_option("--pitch", options.pitch_degrees, "D: the camera D degrees from above (-80..80)")
      ->check(facerig::cli::InRange(-80.0f, 80.0f));
  app.add_option("--size", size, "WxH: frame size in pixels, 16..8192 each (default 640x480; the window's too)");
  app.add_option("--timing", options.timing_json,
                 "FILE: write per-frame CPU timing (update, blend, upload, draw) as JSON");
  app.add_option("--quit-after", options.quit_after, "S: window: quit after S seconds (default: when closed)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--screenshot", options.screenshot, "FILE.png: window: save the last frame");
  AddHeadlessOptions(app, options);
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
  CLI::App app(kDescription, "facerig-player");
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

std::string UsageText() {
  PlayerOptions options;
  std::vector<std::string> emotions;
  std::string size;
  CLI::App app(kDescription, "facerig-player");
  AddPlayerOptions(app, options, emotions, size);
  app.footer(kFooter);
  app.get_formatter()->column_width(24);
  app.get_formatter()->label("OPTIONS", "OPTIONS");
  return app.help();
}

std::vector<std::string> OptionsWithoutDescription() {
  PlayerOptions options;
  std::vector<std::string> emotions;
  std::string size;
  CLI::App app(kDescription, "facerig-player");
  AddPlayerOptions(app, options, emotions, size);
  std::vector<std::string> missing;
  for (const CLI::Option* option : app.get_options()) {
    if (option->get_description().empty()) missing.push_back(option->get_name());
  }
  return missing;
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
