#include "egl_context.h"

#include <cstdio>
#include <stdexcept>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

namespace facerig::player {
namespace {

std::string EglErrorText(const char* what) {
  char text[128];
  std::snprintf(text, sizeof(text), "%s failed (EGL error 0x%04x)", what, eglGetError());
  return text;
}

}  // namespace

HeadlessGlContext::HeadlessGlContext() {
  // Prefer Mesa's surfaceless platform: it needs no X/Wayland server and no
  // DRM device (llvmpipe on CI). eglGetPlatformDisplayEXT rather than the EGL
  // 1.5 entry point, which epoxy only resolves once a display says it is 1.5.
  EGLDisplay display = EGL_NO_DISPLAY;
  std::string platform;
  if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless") &&
      epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_base")) {
    display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    platform = "EGL surfaceless";
  }
  EGLint major = 0, minor = 0;
  if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor)) {
    display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    platform = "EGL default display";
    if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor)) {
      throw std::runtime_error("headless OpenGL: " + EglErrorText("eglInitialize") +
                               "; install Mesa's EGL (Debian: libegl-mesa0 libgl1-mesa-dri)");
    }
  }
  display_ = display;
  if (!eglBindAPI(EGL_OPENGL_API)) throw std::runtime_error("headless OpenGL: " + EglErrorText("eglBindAPI"));

  // A config only matters for its GL capability: we draw into an FBO, never a surface.
  const EGLint config_attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                      EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint config_count = 0;
  eglChooseConfig(display, config_attributes, &config, 1, &config_count);
  const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                       EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                       EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, config_count > 0 ? config : EGL_NO_CONFIG_KHR,
                                        EGL_NO_CONTEXT, context_attributes);
  if (context == EGL_NO_CONTEXT) {
    eglTerminate(display);
    throw std::runtime_error("headless OpenGL: " + EglErrorText("eglCreateContext (OpenGL 3.3 core)"));
  }
  context_ = context;
  // No surface at all (EGL_KHR_surfaceless_context): the renderer's FBO is the target.
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    eglDestroyContext(display, context);
    eglTerminate(display);
    throw std::runtime_error("headless OpenGL: " + EglErrorText("eglMakeCurrent (surfaceless)"));
  }
  description_ = std::string(reinterpret_cast<const char*>(glGetString(GL_RENDERER))) + ", " +
                 reinterpret_cast<const char*>(glGetString(GL_VERSION)) + ", " + platform;
}

HeadlessGlContext::~HeadlessGlContext() {
  const auto display = static_cast<EGLDisplay>(display_);
  eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display, static_cast<EGLContext>(context_));
  // Not eglTerminate: the display is shared per process, and another context
  // (the next test) may still be alive on it.
}

}  // namespace facerig::player
