#include "bench/gl_replay/gl_util.h"

#include <vector>

#include "bench/gl_replay/gl_context.h"

namespace penumbra::gl::detail {
namespace {

GLuint compile(GLenum type, const char* source, const std::string& name) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    GLint len = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
    std::vector<char> log(static_cast<size_t>(len > 1 ? len : 1), '\0');
    glGetShaderInfoLog(shader, len, nullptr, log.data());
    glDeleteShader(shader);
    throw GlError(name + (type == GL_VERTEX_SHADER ? ": vertex" : ": fragment") +
                  " shader does not compile: " + log.data());
  }
  return shader;
}

}  // namespace

GLuint buildProgram(const char* vertexSource, const char* fragmentSource, const std::string& name) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertexSource, name);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, fragmentSource, name);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    GLint len = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &len);
    std::vector<char> log(static_cast<size_t>(len > 1 ? len : 1), '\0');
    glGetProgramInfoLog(program, len, nullptr, log.data());
    glDeleteProgram(program);
    throw GlError(name + ": program does not link: " + log.data());
  }
  return program;
}

void checkFramebuffer(const std::string& name) {
  const GLenum status = glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throw GlError(name + ": framebuffer incomplete (status " + std::to_string(status) + ")");
  }
}

}  // namespace penumbra::gl::detail
