#include "window_player.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <iostream>
#include <memory>

#include <SDL.h>
#include <epoxy/gl.h>

#include "audio_output.h"
#include "face_animator.h"
#include "face_renderer.h"
#include "facerig/espeak/espeak_phoneme_source.h"
#include "frame_timing.h"
#include "hud.h"
#include "media_writer.h"
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
  SdlWindow sdl;
  if (SDL_Init(SDL_INIT_VIDEO) != 0) {
    std::cerr << WindowFailedMessage(SDL_GetError()) << '\n';
    return 1;
  }
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_MAJOR_VERSION, 3);
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_MINOR_VERSION, 3);
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_PROFILE_MASK, SDL_GL_CONTEXT_PROFILE_CORE);
  SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
  SDL_GL_SetAttribute(SDL_GL_DEPTH_SIZE, 24);
  SDL_GL_SetAttribute(SDL_GL_MULTISAMPLEBUFFERS, options.msaa > 0 ? 1 : 0);
  SDL_GL_SetAttribute(SDL_GL_MULTISAMPLESAMPLES, options.msaa);
  const std::string title = "facerig-player - " + rig_name;
  sdl.window = SDL_CreateWindow(title.c_str(), SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, options.width,
                                options.height, SDL_WINDOW_OPENGL | SDL_WINDOW_RESIZABLE | SDL_WINDOW_ALLOW_HIGHDPI);
  if (sdl.window == nullptr) {
    // No multisampled visual (some X servers): try without.
    SDL_GL_SetAttribute(SDL_GL_MULTISAMPLEBUFFERS, 0);
    SDL_GL_SetAttribute(SDL_GL_MULTISAMPLESAMPLES, 0);
    sdl.window = SDL_CreateWindow(title.c_str(), SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, options.width,
                                  options.height, SDL_WINDOW_OPENGL | SDL_WINDOW_RESIZABLE);
  }
  if (sdl.window == nullptr) {
    std::cerr << WindowFailedMessage(SDL_GetError()) << '\n';
    return 1;
  }
  sdl.context = SDL_GL_CreateContext(sdl.window);
  if (sdl.context == nullptr) {
    std::cerr << "facerig-player: no OpenGL 3.3 core context: " << SDL_GetError() << '\n';
    return 1;
  }
  SDL_GL_SetSwapInterval(1);
  std::cout << "OpenGL: " << glGetString(GL_RENDERER) << ", " << glGetString(GL_VERSION) << '\n';

  // Audio: the clock follows the device; without one, the wall clock.
  AudioClock clock;
  AudioOutput audio;
  std::string audio_error;
  if (!audio.Open(EspeakPhonemeSource::kSampleRate, &clock, &audio_error)) {
    std::cerr << "warning: no audio device (" << audio_error
              << "); speaking silently, animation on the wall clock\n";
    clock.StartSilent(WallSeconds());
  }

  IdleLifeParams idle;
  idle.head_motion = idle.saccades = !options.still;
  FaceAnimator animator(rig, idle);
  float intensity = 0.7f;
  std::array<bool, kEmotionCount> emotion_on{};
  for (const auto& [emotion, value] : options.emotions) {
    animator.character().SetEmotion(emotion, value);
    emotion_on[static_cast<std::size_t>(emotion)] = true;
    intensity = value;
  }
  FaceRenderer renderer(rig);
  Hud hud;
  FrameTimer timer;
  SpeechWorker worker;
  if (!options.say.empty()) worker.Request(options.say, options.voice);

  TextLine line;
  std::string message = "voice " + options.voice +
                        ": type a line, Enter speaks it. Empty line: 1-6 emotions, +/- intensity, space pause";
  bool paused = false, dragging = false, swallow_text = false, running = true;
  double paused_time = 0.0;
  SDL_StartTextInput();

  const auto toggle_pause = [&] {
    paused = !paused;
    if (audio.is_open()) {
      audio.SetPaused(paused);
    } else if (paused) {
      clock.Stop(WallSeconds());
    } else {
      clock.StartSilent(WallSeconds());
    }
    paused_time = clock.Now(WallSeconds());
  };

  const double start_wall = WallSeconds();
  Image screenshot;
  while (running) {
    if (options.quit_after > 0.0 && WallSeconds() - start_wall >= options.quit_after) running = false;
    SDL_Event event;
    while (SDL_PollEvent(&event)) {
      switch (event.type) {
        case SDL_QUIT: running = false; break;
        case SDL_TEXTINPUT:
          if (swallow_text) {
            swallow_text = false;  // the key already acted as a command
          } else {
            line.Insert(event.text.text);
          }
          break;
        case SDL_KEYDOWN: {
          const SDL_Keycode key = event.key.keysym.sym;
          swallow_text = false;
          // With an empty line, keys are commands; otherwise they edit the line.
          if (line.text.empty()) {
            if (key >= SDLK_1 && key <= SDLK_6) {
              const auto e = static_cast<std::size_t>(key - SDLK_1);
              emotion_on[e] = !emotion_on[e];
              animator.character().SetEmotion(static_cast<Emotion>(e), emotion_on[e] ? intensity : 0.0f);
              swallow_text = true;
              break;
            }
            if (key == SDLK_PLUS || key == SDLK_EQUALS || key == SDLK_KP_PLUS || key == SDLK_MINUS ||
                key == SDLK_KP_MINUS) {
              const bool up = key == SDLK_PLUS || key == SDLK_EQUALS || key == SDLK_KP_PLUS;
              intensity = std::clamp(intensity + (up ? 0.1f : -0.1f), 0.1f, 1.0f);
              for (std::size_t e = 0; e < kEmotionCount; ++e) {
                if (emotion_on[e]) animator.character().SetEmotion(static_cast<Emotion>(e), intensity);
              }
              swallow_text = true;
              break;
            }
            if (key == SDLK_SPACE) {
              toggle_pause();
              swallow_text = true;
              break;
            }
          }
          switch (key) {
            case SDLK_ESCAPE: running = false; break;
            case SDLK_BACKSPACE: line.Backspace(); break;
            case SDLK_DELETE: line.Delete(); break;
            case SDLK_LEFT: line.cursor = PreviousChar(line.text, line.cursor); break;
            case SDLK_RIGHT: line.cursor = NextChar(line.text, line.cursor); break;
            case SDLK_HOME: line.cursor = 0; break;
            case SDLK_END: line.cursor = line.text.size(); break;
            case SDLK_UP: line.Browse(-1); break;
            case SDLK_DOWN: line.Browse(+1); break;
            case SDLK_TAB: renderer.ResetCamera(); break;
            case SDLK_RETURN:
            case SDLK_KP_ENTER:
              if (!line.text.empty()) worker.Request(line.Take(), options.voice);
              break;
            default: break;
          }
          break;
        }
        case SDL_MOUSEBUTTONDOWN:
          if (event.button.button == SDL_BUTTON_LEFT) dragging = true;
          break;
        case SDL_MOUSEBUTTONUP:
          if (event.button.button == SDL_BUTTON_LEFT) dragging = false;
          break;
        case SDL_MOUSEMOTION:
          if (dragging) {
            renderer.camera().Orbit(-0.4f * static_cast<float>(event.motion.xrel),
                                    0.4f * static_cast<float>(event.motion.yrel));
          }
          break;
        case SDL_MOUSEWHEEL: renderer.camera().Zoom(static_cast<float>(event.wheel.y)); break;
        default: break;
      }
    }

    // A synthesized line: play it and schedule the mouth at the time its first sample is heard.
    if (std::optional<SpeechResult> result = worker.Poll()) {
      if (!result->error.empty()) {
        message = "speech error: " + result->error;
        std::cerr << message << '\n';
      } else {
        const double start = audio.is_open() ? audio.Play(result->line.audio) : clock.Now(WallSeconds());
        const CharacterError error = animator.character().Speak(result->line.phonemes, Seconds(start));
        message = error == CharacterError::kNone ? "\"" + result->text + "\"" : std::string("Speak: ") + ToString(error);
      }
    }

    const double time = paused ? paused_time : clock.Now(WallSeconds());
    int width = 0, height = 0;
    SDL_GL_GetDrawableSize(sdl.window, &width, &height);
    timer.BeginFrame();
    animator.Update(time, &timer);
    renderer.Upload(animator.positions(), animator.normals());
    timer.Mark(Stage::kUpload);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    renderer.Draw(width, height, animator.head_rotation());
    HudState state = MakeHudState(animator, timer, time);
    state.emotion_intensity = intensity;
    state.show_input = true;
    state.input = line.text;
    state.cursor = line.cursor;
    state.status = std::string(paused ? "PAUSED  " : "") + "clock " + ToString(clock.status()) + "  " +
                   (worker.busy() ? "synthesizing...  " : "") + message;
    hud.Draw(state, width, height);
    timer.Mark(Stage::kDraw);
    timer.EndFrame();
    if (!running && !options.screenshot.empty()) ReadBackBuffer(width, height, &screenshot);
    SDL_GL_SwapWindow(sdl.window);
  }
  SDL_StopTextInput();
  if (!options.screenshot.empty() && screenshot.width > 0) {
    WritePng(options.screenshot, screenshot);
    std::cout << "wrote " << options.screenshot.string() << '\n';
  }

  const TimingSummary summary = timer.Summarize();
  std::cout << FormatSummary(summary, "facerig-player " + rig_name);
  if (!options.timing_json.empty()) {
    WriteTimingJson(options.timing_json, summary, timer.samples(), rig_name, rig.vertex_count(), rig.shape_count());
    std::cout << "wrote " << options.timing_json.string() << '\n';
  }
  return 0;
}

}  // namespace facerig::player
