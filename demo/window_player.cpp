#include "window_player.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <optional>
#include <utility>

#include <SDL.h>
#include <epoxy/gl.h>

#include "audio_output.h"
#include "face_animator.h"
#include "face_renderer.h"
#include "facerig/espeak/espeak_phoneme_source.h"
#include "frame_timing.h"
#include "hud.h"
#include "media_writer.h"
#include "recorded_speech.h"
#include "speech_worker.h"

namespace facerig::player {
namespace {

constexpr const char* kHeadlessAdvice =
    "run headless instead (offscreen EGL, no sound card needed):\n"
    "  facerig-player --headless --frames DIR --wav FILE --say \"Hello world\"";

bool Empty(const char* variable) {
  const char* value = std::getenv(variable);
  return value == nullptr || value[0] == '\0';
}

// UTF-8: the byte offset of the character before / after `cursor`.
std::size_t PreviousChar(const std::string& text, std::size_t cursor) {
  if (cursor == 0) return 0;
  --cursor;
  while (cursor > 0 && (static_cast<unsigned char>(text[cursor]) & 0xC0) == 0x80) --cursor;
  return cursor;
}
std::size_t NextChar(const std::string& text, std::size_t cursor) {
  if (cursor >= text.size()) return text.size();
  ++cursor;
  while (cursor < text.size() && (static_cast<unsigned char>(text[cursor]) & 0xC0) == 0x80) ++cursor;
  return cursor;
}

// The text line with editing and history.
struct TextLine {
  std::string text;
  std::size_t cursor = 0;
  std::vector<std::string> history;
  std::size_t history_index = 0;  // == history.size(): editing a new line

  void Insert(const char* utf8) {
    text.insert(cursor, utf8);
    cursor += std::strlen(utf8);
  }
  void Backspace() {
    const std::size_t start = PreviousChar(text, cursor);
    text.erase(start, cursor - start);
    cursor = start;
  }
  void Delete() { text.erase(cursor, NextChar(text, cursor) - cursor); }
  void Browse(int direction) {
    if (history.empty()) return;
    if (direction < 0 && history_index > 0) --history_index;
    if (direction > 0 && history_index < history.size()) ++history_index;
    text = history_index < history.size() ? history[history_index] : std::string();
    cursor = text.size();
  }
  std::string Take() {
    std::string line = std::move(text);
    text.clear();
    cursor = 0;
    if (!line.empty() && (history.empty() || history.back() != line)) history.push_back(line);
    history_index = history.size();
    return line;
  }
};

// The frame just drawn, before the swap.
void ReadBackBuffer(int width, int height, Image* image) {
  image->width = width;
  image->height = height;
  const std::size_t row = static_cast<std::size_t>(width) * 4;
  std::vector<std::uint8_t> pixels(row * static_cast<std::size_t>(height));
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  image->rgba.resize(pixels.size());
  for (int y = 0; y < height; ++y) {  // GL rows go bottom to top
    std::copy_n(pixels.data() + static_cast<std::size_t>(height - 1 - y) * row, row,
                image->rgba.data() + static_cast<std::size_t>(y) * row);
  }
}

struct SdlWindow {
  SDL_Window* window = nullptr;
  SDL_GLContext context = nullptr;
  ~SdlWindow() {
    if (context) SDL_GL_DeleteContext(context);
    if (window) SDL_DestroyWindow(window);
    SDL_Quit();
  }
};

// A GL 3.3 core context, double-buffered, with `msaa` samples (0: none).
void SetGlAttributes(int msaa) {
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_MAJOR_VERSION, 3);
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_MINOR_VERSION, 3);
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_PROFILE_MASK, SDL_GL_CONTEXT_PROFILE_CORE);
  SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
  SDL_GL_SetAttribute(SDL_GL_DEPTH_SIZE, 24);
  SDL_GL_SetAttribute(SDL_GL_MULTISAMPLEBUFFERS, msaa > 0 ? 1 : 0);
  SDL_GL_SetAttribute(SDL_GL_MULTISAMPLESAMPLES, msaa);
}

// Opens the window with a current GL context and vsync. On failure prints why
// (with the headless advice) and returns false.
bool OpenWindow(const std::string& rig_name, const PlayerOptions& options, SdlWindow* sdl) {
  if (SDL_Init(SDL_INIT_VIDEO) != 0) {
    std::cerr << WindowFailedMessage(SDL_GetError()) << '\n';
    return false;
  }
  SetGlAttributes(options.msaa);
  const std::string title = "facerig-player - " + rig_name;
  sdl->window = SDL_CreateWindow(title.c_str(), SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, options.width,
                                 options.height, SDL_WINDOW_OPENGL | SDL_WINDOW_RESIZABLE | SDL_WINDOW_ALLOW_HIGHDPI);
  if (sdl->window == nullptr) {
    // No multisampled visual (some X servers): try without.
    SDL_GL_SetAttribute(SDL_GL_MULTISAMPLEBUFFERS, 0);
    SDL_GL_SetAttribute(SDL_GL_MULTISAMPLESAMPLES, 0);
    sdl->window = SDL_CreateWindow(title.c_str(), SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, options.width,
                                   options.height, SDL_WINDOW_OPENGL | SDL_WINDOW_RESIZABLE);
  }
  if (sdl->window == nullptr) {
    std::cerr << WindowFailedMessage(SDL_GetError()) << '\n';
    return false;
  }
  sdl->context = SDL_GL_CreateContext(sdl->window);
  if (sdl->context == nullptr) {
    std::cerr << "facerig-player: no OpenGL 3.3 core context: " << SDL_GetError() << '\n';
    return false;
  }
  SDL_GL_SetSwapInterval(1);
  std::cout << "OpenGL: " << glGetString(GL_RENDERER) << ", " << glGetString(GL_VERSION) << '\n';
  return true;
}

// The clock follows the audio device; without one, the wall clock.
void OpenAudioOrWallClock(AudioOutput* audio, AudioClock* clock) {
  std::string audio_error;
  if (!audio->Open(EspeakPhonemeSource::kSampleRate, clock, &audio_error)) {
    std::cerr << "warning: no audio device (" << audio_error
              << "); speaking silently, animation on the wall clock\n";
    clock->StartSilent(WallSeconds());
  }
}

// The emotions that keys 1-6 toggle, all at the one intensity that +/- steps.
class EmotionKeys {
 public:
  // Starts with the --emotion options on; the last one's intensity becomes the shared one.
  EmotionKeys(const PlayerOptions& options, Character& character) : character_(character) {
    for (const auto& [emotion, value] : options.emotions) {
      character_.SetEmotion(emotion, value);
      on_[static_cast<std::size_t>(emotion)] = true;
      intensity_ = value;
    }
  }
  void Toggle(std::size_t e) {
    on_[e] = !on_[e];
    character_.SetEmotion(static_cast<Emotion>(e), on_[e] ? intensity_ : 0.0f);
  }
  void StepIntensity(bool up) {
    intensity_ = std::clamp(intensity_ + (up ? 0.1f : -0.1f), 0.1f, 1.0f);
    for (std::size_t e = 0; e < kEmotionCount; ++e) {
      if (on_[e]) character_.SetEmotion(static_cast<Emotion>(e), intensity_);
    }
  }
  float intensity() const { return intensity_; }

 private:
  Character& character_;
  float intensity_ = 0.7f;
  std::array<bool, kEmotionCount> on_{};
};

// The window loop's state: the animation, rendering, speech and the text line.
// Lives inside the window's GL context and after the audio it plays through.
class WindowLoop {
 public:
  WindowLoop(const Rig& rig, const PlayerOptions& options, SDL_Window* window, AudioOutput& audio,
             AudioClock& clock);
  // Until the window closes, Esc or --quit-after; the last frame drawn is the screenshot.
  void Run();

  // Plays `line` (a recording with its phonemes) once the loop runs.
  void SpeakRecording(SpeechLine line);

  const FrameTimer& timer() const { return timer_; }
  // Read back only with --screenshot (width 0 otherwise).
  const Image& screenshot() const { return screenshot_; }

 private:
  void HandleEvents();
  void HandleText(const char* utf8);
  void HandleKey(SDL_Keycode key);
  // Emotions, intensity and pause. Returns false for keys that are not commands.
  bool HandleCommandKey(SDL_Keycode key);
  void HandleEditKey(SDL_Keycode key);
  void TogglePause();
  void PlayFinishedSpeech();
  void DrawFrame();
  HudState MakeWindowHudState(double time);

  const PlayerOptions& options_;
  SDL_Window* window_;
  AudioOutput& audio_;
  AudioClock& clock_;
  FaceAnimator animator_;
  EmotionKeys emotions_;
  FaceRenderer renderer_;
  Hud hud_;
  FrameTimer timer_;
  SpeechWorker worker_;
  std::optional<SpeechResult> recorded_;  // --audio / --track: played on the first frame
  TextLine line_;
  std::string message_;
  bool paused_ = false, dragging_ = false, swallow_text_ = false, running_ = true;
  double paused_time_ = 0.0;
  Image screenshot_;
};

IdleLifeParams IdleFor(const PlayerOptions& options) {
  IdleLifeParams idle;
  idle.head_motion = idle.saccades = !options.still;
  return idle;
}

WindowLoop::WindowLoop(const Rig& rig, const PlayerOptions& options, SDL_Window* window, AudioOutput& audio,
                       AudioClock& clock)
    : options_(options),
      window_(window),
      audio_(audio),
      clock_(clock),
      animator_(rig, IdleFor(options)),
      emotions_(options, animator_.character()),
      renderer_(rig),
      message_("voice " + options.voice +
               ": type a line, Enter speaks it. Empty line: 1-6 emotions, +/- intensity, space pause") {
  for (const std::string& problem : renderer_.problems()) std::cerr << "warning: " << problem << '\n';
  renderer_.camera().Orbit(options.yaw_degrees, options.pitch_degrees);
  if (options.recomputed_normals) animator_.SetNormalMode(NormalMode::kRecompute);
  if (!options.say.empty()) worker_.Request(options.say, options.voice);
}

void WindowLoop::SpeakRecording(SpeechLine line) {
  recorded_ = SpeechResult{line.text, std::move(line), {}};
}

void WindowLoop::Run() {
  SDL_StartTextInput();
  const double start_wall = WallSeconds();
  while (running_) {
    if (options_.quit_after > 0.0 && WallSeconds() - start_wall >= options_.quit_after) running_ = false;
    HandleEvents();
    PlayFinishedSpeech();
    DrawFrame();
  }
  SDL_StopTextInput();
}

void WindowLoop::HandleEvents() {
  SDL_Event event;
  while (SDL_PollEvent(&event)) {
    switch (event.type) {
      case SDL_QUIT: running_ = false; break;
      case SDL_TEXTINPUT: HandleText(event.text.text); break;
      case SDL_KEYDOWN: HandleKey(event.key.keysym.sym); break;
      case SDL_MOUSEBUTTONDOWN:
        if (event.button.button == SDL_BUTTON_LEFT) dragging_ = true;
        break;
      case SDL_MOUSEBUTTONUP:
        if (event.button.button == SDL_BUTTON_LEFT) dragging_ = false;
        break;
      case SDL_MOUSEMOTION:
        if (dragging_) {
          renderer_.camera().Orbit(-0.4f * static_cast<float>(event.motion.xrel),
                                   0.4f * static_cast<float>(event.motion.yrel));
        }
        break;
      case SDL_MOUSEWHEEL: renderer_.camera().Zoom(static_cast<float>(event.wheel.y)); break;
      default: break;
    }
  }
}

void WindowLoop::HandleText(const char* utf8) {
  if (swallow_text_) {
    swallow_text_ = false;  // the key already acted as a command
  } else {
    line_.Insert(utf8);
  }
}

void WindowLoop::HandleKey(SDL_Keycode key) {
  swallow_text_ = false;
  // With an empty line, keys are commands; otherwise they edit the line.
  if (line_.text.empty() && HandleCommandKey(key)) {
    swallow_text_ = true;
    return;
  }
  HandleEditKey(key);
}

bool WindowLoop::HandleCommandKey(SDL_Keycode key) {
  if (key >= SDLK_1 && key <= SDLK_6) {
    emotions_.Toggle(static_cast<std::size_t>(key - SDLK_1));
    return true;
  }
  const bool up = key == SDLK_PLUS || key == SDLK_EQUALS || key == SDLK_KP_PLUS;
  if (up || key == SDLK_MINUS || key == SDLK_KP_MINUS) {
    emotions_.StepIntensity(up);
    return true;
  }
  if (key == SDLK_SPACE) {
    TogglePause();
    return true;
  }
  return false;
}

void WindowLoop::HandleEditKey(SDL_Keycode key) {
  switch (key) {
    case SDLK_ESCAPE: running_ = false; break;
    case SDLK_BACKSPACE: line_.Backspace(); break;
    case SDLK_DELETE: line_.Delete(); break;
    case SDLK_LEFT: line_.cursor = PreviousChar(line_.text, line_.cursor); break;
    case SDLK_RIGHT: line_.cursor = NextChar(line_.text, line_.cursor); break;
    case SDLK_HOME: line_.cursor = 0; break;
    case SDLK_END: line_.cursor = line_.text.size(); break;
    case SDLK_UP: line_.Browse(-1); break;
    case SDLK_DOWN: line_.Browse(+1); break;
    case SDLK_TAB: renderer_.ResetCamera(); break;
    case SDLK_RETURN:
    case SDLK_KP_ENTER:
      if (!line_.text.empty()) worker_.Request(line_.Take(), options_.voice);
      break;
    default: break;
  }
}

void WindowLoop::TogglePause() {
  paused_ = !paused_;
  if (audio_.is_open()) {
    audio_.SetPaused(paused_);
  } else if (paused_) {
    clock_.Stop(WallSeconds());
  } else {
    clock_.StartSilent(WallSeconds());
  }
  paused_time_ = clock_.Now(WallSeconds());
}

// A synthesized line: play it and schedule the mouth at the time its first sample is heard.
void WindowLoop::PlayFinishedSpeech() {
  std::optional<SpeechResult> result = recorded_ ? std::exchange(recorded_, std::nullopt) : worker_.Poll();
  if (!result) return;
  if (!result->error.empty()) {
    message_ = "speech error: " + result->error;
    std::cerr << message_ << '\n';
    return;
  }
  const double start = audio_.is_open() ? audio_.Play(result->line.audio) : clock_.Now(WallSeconds());
  const CharacterError error = animator_.character().Speak(result->line.phonemes, Seconds(start));
  message_ = error == CharacterError::kNone ? "\"" + result->text + "\"" : std::string("Speak: ") + ToString(error);
}

void WindowLoop::DrawFrame() {
  const double time = paused_ ? paused_time_ : clock_.Now(WallSeconds());
  int width = 0, height = 0;
  SDL_GL_GetDrawableSize(window_, &width, &height);
  timer_.BeginFrame();
  animator_.Update(time, &timer_);
  renderer_.Upload(animator_.positions(), animator_.normals());
  timer_.Mark(Stage::kUpload);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  renderer_.Draw(width, height, animator_.head_rotation());
  hud_.Draw(MakeWindowHudState(time), width, height);
  timer_.Mark(Stage::kDraw);
  timer_.EndFrame();
  if (!running_ && !options_.screenshot.empty()) ReadBackBuffer(width, height, &screenshot_);
  SDL_GL_SwapWindow(window_);
}

// The headless HUD plus the text line and the status line.
HudState WindowLoop::MakeWindowHudState(double time) {
  HudState state = MakeHudState(animator_, timer_, time);
  state.emotion_intensity = emotions_.intensity();
  state.show_input = true;
  state.input = line_.text;
  state.cursor = line_.cursor;
  state.status = std::string(paused_ ? "PAUSED  " : "") + "clock " + ToString(clock_.status()) + "  " +
                 (worker_.busy() ? "synthesizing...  " : "") + message_;
  return state;
}

// The --screenshot PNG, when a frame was read back.
void WriteScreenshot(const PlayerOptions& options, const Image& screenshot) {
  if (options.screenshot.empty() || screenshot.width <= 0) return;
  WritePng(options.screenshot, screenshot);
  std::cout << "wrote " << options.screenshot.string() << '\n';
}

void ReportTiming(const FrameTimer& timer, const Rig& rig, const std::string& rig_name,
                  const PlayerOptions& options) {
  const TimingSummary summary = timer.Summarize();
  std::cout << FormatSummary(summary, "facerig-player " + rig_name);
  if (!options.timing_json.empty()) {
    WriteTimingJson(options.timing_json, summary, timer.samples(), rig_name, rig.vertex_count(), rig.shape_count());
    std::cout << "wrote " << options.timing_json.string() << '\n';
  }
}

}  // namespace

std::optional<std::string> NoDisplayMessage() {
  if (Empty("DISPLAY") && Empty("WAYLAND_DISPLAY") && Empty("SDL_VIDEODRIVER")) {
    return std::string("facerig-player: no display (DISPLAY and WAYLAND_DISPLAY are not set), so no window; ") +
           kHeadlessAdvice;
  }
  return std::nullopt;
}

std::string WindowFailedMessage(const std::string& reason) {
  return "facerig-player: cannot open a window (" + reason + "); " + kHeadlessAdvice;
}

int RunWindow(const Rig& rig, const std::string& rig_name, const PlayerOptions& options) {
  // Before the window: a bad recording or track fails at once.
  std::optional<SpeechLine> recording;
  if (WantsRecordedSpeech(options)) recording = LoadRecordedSpeech(options, EspeakPhonemeSource::kSampleRate);
  SdlWindow sdl;  // SDL_Quit on every return
  if (!OpenWindow(rig_name, options, &sdl)) return 1;
  AudioClock clock;
  AudioOutput audio;
  OpenAudioOrWallClock(&audio, &clock);
  WindowLoop loop(rig, options, sdl.window, audio, clock);
  if (recording) loop.SpeakRecording(std::move(*recording));
  loop.Run();
  WriteScreenshot(options, loop.screenshot());
  ReportTiming(loop.timer(), rig, rig_name, options);
  return 0;
}

}  // namespace facerig::player
