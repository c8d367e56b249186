// The player's heads-up display: text from a built-in 5x7 bitmap font and
// weight bars, drawn as coloured GL quads in pixel coordinates (no font files).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/vec4.hpp>

#include "facerig/runtime/behaviour/emotion.h"
#include "frame_timing.h"

namespace facerig::player {

class FaceAnimator;

struct HudState {
  double time = 0.0;
  std::string phoneme;  // under the clock, "" in silence
  std::string viseme;
  std::vector<std::pair<std::string, float>> weights;  // the non-zero ones
  std::array<float, kEmotionCount> emotions{};         // current intensities
  float emotion_intensity = 0.0f;                      // what 1-6 set
  double frame_p50_ms = 0.0, frame_p99_ms = 0.0;
  std::string status;         // clock, voice, synthesis state, errors
  bool show_input = false;
  std::string input;          // the text line
  std::size_t cursor = 0;     // byte offset in input
};

// Phoneme, viseme, active weights and emotions from the animator; frame
// times over the last 120 frames of `timer`.
HudState MakeHudState(FaceAnimator& animator, const FrameTimer& timer, double time);

class Hud {
 public:
  Hud();  // needs a current GL 3.3 context
  ~Hud();
  Hud(const Hud&) = delete;
  Hud& operator=(const Hud&) = delete;

  // Draws over the bound framebuffer (viewport width x height).
  void Draw(const HudState& state, int width, int height);

 private:
  struct Layout;
  void DrawStatusPanel(const HudState& state, const Layout& layout);
  void DrawWeightBars(const HudState& state, const Layout& layout);
  void DrawInputLine(const HudState& state, const Layout& layout);
  void Submit(int width, int height);
  void Rect(float x, float y, float w, float h, const glm::vec4& color);
  // Returns the x after the text.
  float Text(float x, float y, std::string_view text, const glm::vec4& color, float scale);

  std::vector<float> vertices_;  // x, y, r, g, b, a per vertex; two triangles per quad
  unsigned program_ = 0, vao_ = 0, vbo_ = 0;
  int u_viewport_ = -1;
};

}  // namespace facerig::player
