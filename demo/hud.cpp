#include "hud.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>

#include <epoxy/gl.h>

#include "face_animator.h"
#include "face_renderer.h"

namespace facerig::player {
namespace {

// The classic 5x7 LCD font, ASCII 32..126: five columns per glyph, bit 0 at the top.
constexpr std::uint8_t kFont5x7[95][5] = {
    {0x00, 0x00, 0x00, 0x00, 0x00}, {0x00, 0x00, 0x5F, 0x00, 0x00}, {0x00, 0x07, 0x00, 0x07, 0x00},
    {0x14, 0x7F, 0x14, 0x7F, 0x14}, {0x24, 0x2A, 0x7F, 0x2A, 0x12}, {0x23, 0x13, 0x08, 0x64, 0x62},
    {0x36, 0x49, 0x55, 0x22, 0x50}, {0x00, 0x05, 0x03, 0x00, 0x00}, {0x00, 0x1C, 0x22, 0x41, 0x00},
    {0x00, 0x41, 0x22, 0x1C, 0x00}, {0x08, 0x2A, 0x1C, 0x2A, 0x08}, {0x08, 0x08, 0x3E, 0x08, 0x08},
    {0x00, 0x50, 0x30, 0x00, 0x00}, {0x08, 0x08, 0x08, 0x08, 0x08}, {0x00, 0x60, 0x60, 0x00, 0x00},
    {0x20, 0x10, 0x08, 0x04, 0x02}, {0x3E, 0x51, 0x49, 0x45, 0x3E}, {0x00, 0x42, 0x7F, 0x40, 0x00},
    {0x42, 0x61, 0x51, 0x49, 0x46}, {0x21, 0x41, 0x45, 0x4B, 0x31}, {0x18, 0x14, 0x12, 0x7F, 0x10},
    {0x27, 0x45, 0x45, 0x45, 0x39}, {0x3C, 0x4A, 0x49, 0x49, 0x30}, {0x01, 0x71, 0x09, 0x05, 0x03},
    {0x36, 0x49, 0x49, 0x49, 0x36}, {0x06, 0x49, 0x49, 0x29, 0x1E}, {0x00, 0x36, 0x36, 0x00, 0x00},
    {0x00, 0x56, 0x36, 0x00, 0x00}, {0x08, 0x14, 0x22, 0x41, 0x00}, {0x14, 0x14, 0x14, 0x14, 0x14},
    {0x00, 0x41, 0x22, 0x14, 0x08}, {0x02, 0x01, 0x51, 0x09, 0x06}, {0x32, 0x49, 0x79, 0x41, 0x3E},
    {0x7E, 0x11, 0x11, 0x11, 0x7E}, {0x7F, 0x49, 0x49, 0x49, 0x36}, {0x3E, 0x41, 0x41, 0x41, 0x22},
    {0x7F, 0x41, 0x41, 0x22, 0x1C}, {0x7F, 0x49, 0x49, 0x49, 0x41}, {0x7F, 0x09, 0x09, 0x01, 0x01},
    {0x3E, 0x41, 0x41, 0x51, 0x32}, {0x7F, 0x08, 0x08, 0x08, 0x7F}, {0x00, 0x41, 0x7F, 0x41, 0x00},
    {0x20, 0x40, 0x41, 0x3F, 0x01}, {0x7F, 0x08, 0x14, 0x22, 0x41}, {0x7F, 0x40, 0x40, 0x40, 0x40},
    {0x7F, 0x02, 0x04, 0x02, 0x7F}, {0x7F, 0x04, 0x08, 0x10, 0x7F}, {0x3E, 0x41, 0x41, 0x41, 0x3E},
    {0x7F, 0x09, 0x09, 0x09, 0x06}, {0x3E, 0x41, 0x51, 0x21, 0x5E}, {0x7F, 0x09, 0x19, 0x29, 0x46},
    {0x46, 0x49, 0x49, 0x49, 0x31}, {0x01, 0x01, 0x7F, 0x01, 0x01}, {0x3F, 0x40, 0x40, 0x40, 0x3F},
    {0x1F, 0x20, 0x40, 0x20, 0x1F}, {0x7F, 0x20, 0x18, 0x20, 0x7F}, {0x63, 0x14, 0x08, 0x14, 0x63},
    {0x03, 0x04, 0x78, 0x04, 0x03}, {0x61, 0x51, 0x49, 0x45, 0x43}, {0x00, 0x7F, 0x41, 0x41, 0x00},
    {0x02, 0x04, 0x08, 0x10, 0x20}, {0x00, 0x41, 0x41, 0x7F, 0x00}, {0x04, 0x02, 0x01, 0x02, 0x04},
    {0x40, 0x40, 0x40, 0x40, 0x40}, {0x00, 0x01, 0x02, 0x04, 0x00}, {0x20, 0x54, 0x54, 0x54, 0x78},
    {0x7F, 0x48, 0x44, 0x44, 0x38}, {0x38, 0x44, 0x44, 0x44, 0x20}, {0x38, 0x44, 0x44, 0x48, 0x7F},
    {0x38, 0x54, 0x54, 0x54, 0x18}, {0x08, 0x7E, 0x09, 0x01, 0x02}, {0x08, 0x14, 0x54, 0x54, 0x3C},
    {0x7F, 0x08, 0x04, 0x04, 0x78}, {0x00, 0x44, 0x7D, 0x40, 0x00}, {0x20, 0x40, 0x44, 0x3D, 0x00},
    {0x00, 0x7F, 0x10, 0x28, 0x44}, {0x00, 0x41, 0x7F, 0x40, 0x00}, {0x7C, 0x04, 0x18, 0x04, 0x78},
    {0x7C, 0x08, 0x04, 0x04, 0x78}, {0x38, 0x44, 0x44, 0x44, 0x38}, {0x7C, 0x14, 0x14, 0x14, 0x08},
    {0x08, 0x14, 0x14, 0x18, 0x7C}, {0x7C, 0x08, 0x04, 0x04, 0x08}, {0x48, 0x54, 0x54, 0x54, 0x20},
    {0x04, 0x3F, 0x44, 0x40, 0x20}, {0x3C, 0x40, 0x40, 0x20, 0x7C}, {0x1C, 0x20, 0x40, 0x20, 0x1C},
    {0x3C, 0x40, 0x30, 0x40, 0x3C}, {0x44, 0x28, 0x10, 0x28, 0x44}, {0x0C, 0x50, 0x50, 0x50, 0x3C},
    {0x44, 0x64, 0x54, 0x4C, 0x44}, {0x00, 0x08, 0x36, 0x41, 0x00}, {0x00, 0x00, 0x7F, 0x00, 0x00},
    {0x00, 0x41, 0x36, 0x08, 0x00}, {0x02, 0x01, 0x02, 0x04, 0x02},
};
constexpr float kGlyphAdvance = 6.0f;  // 5 columns + 1 space
constexpr float kLineHeight = 9.0f;

const char* const kHudVertexShader = R"(#version 330 core
layout(location = 0) in vec2 a_pixel;
layout(location = 1) in vec4 a_color;
uniform vec2 u_viewport;
out vec4 v_color;
void main() {
  v_color = a_color;
  gl_Position = vec4(a_pixel.x / u_viewport.x * 2.0 - 1.0, 1.0 - a_pixel.y / u_viewport.y * 2.0, 0.0, 1.0);
}
)";
const char* const kHudFragmentShader = R"(#version 330 core
in vec4 v_color;
out vec4 frag_color;
void main() { frag_color = v_color; }
)";

std::string Fixed(double value, int decimals) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.*f", decimals, value);
  return text;
}

}  // namespace

HudState MakeHudState(FaceAnimator& animator, const FrameTimer& timer, double time) {
  HudState state;
  state.time = time;
  const Character& character = animator.character();
  if (const Phoneme* phoneme = character.current_phoneme()) state.phoneme = std::string(phoneme->symbol.view());
  state.viseme = std::string(ToString(character.dominant_viseme()));
  const std::span<const float> weights = animator.weights();
  for (std::size_t i = 0; i < weights.size(); ++i) {
    if (weights[i] > 0.005f) state.weights.emplace_back(std::string(animator.rig().shape_name(i)), weights[i]);
  }
  std::sort(state.weights.begin(), state.weights.end(),
            [](const auto& a, const auto& b) { return a.second > b.second; });
  for (std::size_t e = 0; e < kEmotionCount; ++e) {
    state.emotions[e] = animator.character().emotion_state().intensity[e];
  }
  if (!timer.samples().empty()) {
    const TimingSummary summary = timer.Summarize(120);
    state.frame_p50_ms = summary.total.p50;
    state.frame_p99_ms = summary.total.p99;
  }
  return state;
}

Hud::Hud() {
  program_ = CompileProgram(kHudVertexShader, kHudFragmentShader, "hud");
  u_viewport_ = glGetUniformLocation(program_, "u_viewport");
  glGenVertexArrays(1, &vao_);
  glBindVertexArray(vao_);
  glGenBuffers(1, &vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                        reinterpret_cast<const void*>(2 * sizeof(float)));
  glEnableVertexAttribArray(1);
  glBindVertexArray(0);
  vertices_.reserve(6 * 6 * 20000);
}

Hud::~Hud() {
  glDeleteBuffers(1, &vbo_);
  glDeleteVertexArrays(1, &vao_);
  glDeleteProgram(program_);
}

void Hud::Rect(float x, float y, float w, float h, const glm::vec4& color) {
  const float corners[6][2] = {{x, y}, {x + w, y}, {x + w, y + h}, {x, y}, {x + w, y + h}, {x, y + h}};
  for (const auto& corner : corners) {
    vertices_.insert(vertices_.end(), {corner[0], corner[1], color.r, color.g, color.b, color.a});
  }
}

float Hud::Text(float x, float y, std::string_view text, const glm::vec4& color, float scale) {
  for (char c : text) {
    // Non-ASCII bytes (UTF-8) show as '?': the font has ASCII only.
    const int index = (c >= 32 && c <= 126) ? c - 32 : '?' - 32;
    for (int column = 0; column < 5; ++column) {
      const std::uint8_t bits = kFont5x7[index][column];
      for (int row = 0; row < 7; ++row) {
        if (bits & (1u << row)) {
          Rect(x + static_cast<float>(column) * scale, y + static_cast<float>(row) * scale, scale, scale, color);
        }
      }
    }
    x += kGlyphAdvance * scale;
  }
  return x;
}

// Sizes and colours of one frame's HUD.
struct Hud::Layout {
  float w = 0.0f, h = 0.0f;
  float scale = 1.0f, line = 0.0f, margin = 0.0f;
  glm::vec4 white{0.95f, 0.95f, 0.95f, 1.0f}, dim{0.7f, 0.75f, 0.8f, 1.0f};
  glm::vec4 accent{1.0f, 0.8f, 0.35f, 1.0f}, panel{0.0f, 0.0f, 0.0f, 0.45f};
  float TextWidth(std::size_t chars) const { return static_cast<float>(chars) * kGlyphAdvance * scale; }
};

void Hud::Draw(const HudState& state, int width, int height) {
  vertices_.clear();
  Layout layout;
  layout.w = static_cast<float>(width);
  layout.h = static_cast<float>(height);
  // Pixel-doubled on large windows only: at 2x the bars would cover the face.
  layout.scale = (height >= 900 && width >= 1200) ? 2.0f : 1.0f;
  layout.line = kLineHeight * layout.scale;
  layout.margin = 6.0f * layout.scale;
  DrawStatusPanel(state, layout);
  DrawWeightBars(state, layout);
  DrawInputLine(state, layout);
  Submit(width, height);
}

// Top left: clock, phoneme and viseme, frame time, emotions, on a panel wide
// enough for the emotion line (the longest).
void Hud::DrawStatusPanel(const HudState& state, const Layout& l) {
  const float scale = l.scale;
  Rect(0.0f, 0.0f, l.margin * 2.0f + l.TextWidth(62), l.margin + 3.0f * l.line + 2.0f * scale, l.panel);
  float y = l.margin;
  float x = Text(l.margin, y, "t " + Fixed(state.time, 2) + " s   phoneme ", l.dim, scale);
  x = Text(x, y, state.phoneme.empty() ? "-" : state.phoneme, l.accent, scale);
  x = Text(x, y, "   viseme ", l.dim, scale);
  Text(x, y, state.viseme, l.accent, scale);
  y += l.line;
  Text(l.margin, y,
       "frame p50 " + Fixed(state.frame_p50_ms, 2) + " ms  p99 " + Fixed(state.frame_p99_ms, 2) + " ms", l.dim,
       scale);
  y += l.line;
  x = l.margin;
  for (std::size_t e = 0; e < kEmotionCount; ++e) {
    const glm::vec4 color = state.emotions[e] > 0.01f ? l.accent : l.dim;
    x = Text(x, y, std::to_string(e + 1) + " " + std::string(ToString(static_cast<Emotion>(e))) + " ", color, scale);
  }
  Text(x, y, "(+/- " + Fixed(state.emotion_intensity, 1) + ")", l.dim, scale);
}

// Right: a bar per active weight, largest first, as many as fit.
void Hud::DrawWeightBars(const HudState& state, const Layout& l) {
  const float bar_width = 60.0f * l.scale, name_width = 18.0f * kGlyphAdvance * l.scale;
  const float left = l.w - l.margin - bar_width - name_width;
  float bar_y = l.margin + 3.0f * l.line + 4.0f * l.scale;  // below the top-left panel's rows
  const float bottom_reserved = (state.show_input ? 3.0f : 1.0f) * l.line + l.margin;
  for (const auto& [name, value] : state.weights) {
    if (bar_y + l.line > l.h - bottom_reserved) break;
    Rect(left - 2.0f, bar_y - 1.0f, name_width + bar_width + 4.0f, l.line, l.panel);
    Text(left, bar_y, name.substr(0, 17), l.white, l.scale);
    Rect(left + name_width, bar_y, bar_width * std::clamp(value, 0.0f, 1.0f), 7.0f * l.scale,
         glm::vec4(0.35f, 0.75f, 1.0f, 0.9f));
    bar_y += l.line;
  }
}

// Bottom: status and the text line.
void Hud::DrawInputLine(const HudState& state, const Layout& l) {
  const float scale = l.scale;
  float bottom = l.h - l.margin - l.line;
  if (state.show_input) {
    Rect(0.0f, bottom - 3.0f * scale, l.w, l.line + 6.0f * scale, l.panel);
    const float after_prompt = Text(l.margin, bottom, "> ", l.accent, scale);
    Text(after_prompt, bottom, state.input, l.white, scale);
    // The cursor sits after `cursor` bytes; every byte draws one glyph.
    const float cursor_x = after_prompt + static_cast<float>(state.cursor) * kGlyphAdvance * scale;
    Rect(cursor_x - 1.0f, bottom - scale, scale, 9.0f * scale, l.accent);
    bottom -= l.line + 4.0f * scale;
  }
  if (!state.status.empty()) {
    Rect(0.0f, bottom - 2.0f * scale, l.margin * 2.0f + l.TextWidth(state.status.size()), l.line + 2.0f * scale,
         l.panel);
    Text(l.margin, bottom, state.status, l.dim, scale);
  }
}

void Hud::Submit(int width, int height) {
  glViewport(0, 0, width, height);
  glDisable(GL_DEPTH_TEST);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glUseProgram(program_);
  glUniform2f(u_viewport_, static_cast<float>(width), static_cast<float>(height));
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  // Orphan and refill: the HUD is rebuilt every frame.
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices_.size() * sizeof(float)), vertices_.data(),
               GL_STREAM_DRAW);
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(vertices_.size() / 6));
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
}

}  // namespace facerig::player
