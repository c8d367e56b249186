#include <stdexcept>
#include <string>

#include <epoxy/gl.h>

#include "face_renderer.h"

namespace facerig::player {
namespace {

// Throws with the info log (and deletes `object`) when its compile or link
// `status` is false. Shaders and programs have the same three calls under
// different names.
template <typename GetStatus, typename GetLog, typename Delete>
void ThrowUnlessOk(GLuint object, GLenum status, GetStatus get_status, GetLog get_log, Delete destroy,
                   const std::string& what) {
  GLint ok = 0;
  get_status(object, status, &ok);
  if (ok) return;
  char log[2048] = {};
  get_log(object, sizeof(log), nullptr, log);
  destroy(object);
  throw std::runtime_error(what + ": " + log);
}

}  // namespace

unsigned CompileProgram(const char* vertex_source, const char* fragment_source, const char* name) {
  const auto compile = [&](GLenum type, const char* source) {
    const GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    ThrowUnlessOk(shader, GL_COMPILE_STATUS, glGetShaderiv, glGetShaderInfoLog, glDeleteShader,
                  std::string(name) + " shader");
    return shader;
  };
  const GLuint vertex = compile(GL_VERTEX_SHADER, vertex_source);
  const GLuint fragment = compile(GL_FRAGMENT_SHADER, fragment_source);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vertex);
  glAttachShader(program, fragment);
  glLinkProgram(program);
  glDeleteShader(vertex);
  glDeleteShader(fragment);
  ThrowUnlessOk(program, GL_LINK_STATUS, glGetProgramiv, glGetProgramInfoLog, glDeleteProgram,
                std::string(name) + " program");
  return program;
}

}  // namespace facerig::player
