// A headless OpenGL 3.3 core context (EGL, no window, no display server),
// for --headless and the tests. Renders go into an FBO (see FaceRenderer).
#pragma once

#include <string>

namespace facerig::player {

class HeadlessGlContext {
 public:
  // Creates the context and makes it current on this thread. Throws
  // std::runtime_error saying what failed (no EGL, no GL 3.3 core, ...).
  HeadlessGlContext();
  ~HeadlessGlContext();
  HeadlessGlContext(const HeadlessGlContext&) = delete;
  HeadlessGlContext& operator=(const HeadlessGlContext&) = delete;

  // "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa 22.3.6, EGL surfaceless".
  const std::string& description() const { return description_; }

 private:
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  std::string description_;
};

}  // namespace facerig::player
