#include "player_options.h"

#include <algorithm>
#include <charconv>
#include <cmath>

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
       facerig-player [--quit-after S] [--screenshot FILE.png]
       facerig-player --headless --frames DIR [--wav FILE] [--mp4 FILE] [--fps 30]
                      [--size WxH] [--duration S] [--lead-in S] [--say TEXT] [--hud] ...

  --rig FILE       .glb, .gltf, .frig or an OBJ template folder
                   (default: the built-in head the build generates, else ../shared/data/ict-facekit)
  --say TEXT       speak TEXT at start
  --voice V        espeak-ng voice / language (default en-us)
  --emotion E[:I]  joy, sadness, fear, anger, surprise or disgust at intensity I (default 0.7)
  --still          no idle head motion or eye saccades (blinks stay)
  --msaa N         anti-aliasing samples: 0, 2, 4 (default) or 8
  --timing FILE    write per-frame CPU timing (update, blend, normals, upload, draw) as JSON
  --quit-after S   window: quit after S seconds; --screenshot FILE saves the last frame (PNG)
  --headless       no window and no sound card: render offscreen (EGL), animation time =
                   frame / fps; writes DIR/frame_00000.png ... and the speech as a WAV
  --lead-in S      headless: the speech starts S seconds after frame 0 (default 0.3), so the
                   first frame is the face at rest; the WAV holds the speech only (the MP4
                   offsets it by S)
  --hud            headless: draw the HUD into the frames

window keys: type a line and press Enter to speak it (Up/Down: history); with an empty line:
  1-6 toggle joy, sadness, fear, anger, surprise, disgust; +/- intensity; space pause;
  Esc quit. Drag to orbit, scroll to zoom, Tab resets the camera. --size WxH sizes the window.
)";
}

PlayerOptions ParseOptions(const std::vector<std::string>& args) {
  PlayerOptions options;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& flag = args[i];
    const auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw UsageError(flag + " needs a value");
      return args[++i];
    };
    if (flag == "-h" || flag == "--help") {
      options.help = true;
    } else if (flag == "--rig") {
      options.rig = value();
    } else if (flag == "--say") {
      options.say = value();
    } else if (flag == "--voice") {
      options.voice = value();
    } else if (flag == "--emotion") {
      const std::string text = value();
      const std::size_t colon = text.find(':');
      const std::optional<Emotion> emotion = ParseEmotion(text.substr(0, colon));
      if (!emotion) {
        throw UsageError("--emotion: unknown emotion '" + text.substr(0, colon) +
                         "' (joy, sadness, fear, anger, surprise, disgust)");
      }
      const double intensity = colon == std::string::npos ? 0.7 : ParseNumber(flag, text.substr(colon + 1));
      options.emotions.emplace_back(*emotion, static_cast<float>(std::clamp(intensity, 0.0, 1.0)));
    } else if (flag == "--still") {
      options.still = true;
    } else if (flag == "--hud") {
      options.hud = true;
    } else if (flag == "--timing") {
      options.timing_json = value();
    } else if (flag == "--headless") {
      options.headless = true;
    } else if (flag == "--frames") {
      options.frames_dir = value();
    } else if (flag == "--wav") {
      options.wav = value();
    } else if (flag == "--mp4") {
      options.mp4 = value();
    } else if (flag == "--fps") {
      options.fps = ParseNumber(flag, value());
      if (options.fps <= 0.0 || options.fps > 1000.0) throw UsageError("--fps must be in (0, 1000]");
    } else if (flag == "--duration") {
      options.duration = ParseNumber(flag, value());
      if (*options.duration <= 0.0 || *options.duration > 3600.0) {
        throw UsageError("--duration must be in (0, 3600] seconds");
      }
    } else if (flag == "--msaa") {
      const double samples = ParseNumber(flag, value());
      if (samples != 0 && samples != 2 && samples != 4 && samples != 8) throw UsageError("--msaa must be 0, 2, 4 or 8");
      options.msaa = static_cast<int>(samples);
    } else if (flag == "--quit-after") {
      options.quit_after = ParseNumber(flag, value());
      if (options.quit_after < 0.0) throw UsageError("--quit-after must be >= 0 seconds");
    } else if (flag == "--screenshot") {
      options.screenshot = value();
    } else if (flag == "--lead-in") {
      options.lead_in = ParseNumber(flag, value());
      if (options.lead_in < 0.0 || options.lead_in > 60.0) throw UsageError("--lead-in must be in [0, 60] seconds");
    } else if (flag == "--size") {
      const std::string text = value();
      const std::size_t x = text.find('x');
      if (x == std::string::npos) throw UsageError("--size: expected WxH, got '" + text + "'");
      const double w = ParseNumber(flag, text.substr(0, x)), h = ParseNumber(flag, text.substr(x + 1));
      if (w < 16 || h < 16 || w > 8192 || h > 8192 || w != std::floor(w) || h != std::floor(h)) {
        throw UsageError("--size: width and height must be whole numbers in [16, 8192]");
      }
      options.width = static_cast<int>(w);
      options.height = static_cast<int>(h);
    } else {
      throw UsageError("unknown argument '" + flag + "'");
    }
  }
  if (options.headless && options.frames_dir.empty() && !options.help) {
    throw UsageError("--headless needs --frames DIR");
  }
  if (!options.headless && (!options.frames_dir.empty() || !options.wav.empty() || !options.mp4.empty())) {
    throw UsageError("--frames, --wav and --mp4 need --headless");
  }
  return options;
}

std::filesystem::path DefaultRigPath() {
  const std::filesystem::path default_head = FACERIG_DEFAULT_HEAD;
  std::error_code error;
  if (std::filesystem::exists(default_head, error)) return default_head;
  return std::filesystem::path(FACERIG_SHARED_DATA_DIR) / "ict-facekit";
}

}  // namespace facerig::player
