#include "bench/gl_replay/gl_util.h"

#include <string>
#include <vector>

#include "bench/gl_replay/gl_context.h"

namespace penumbra::gl::detail {
namespace {

// The info log of a shader or program (GL keeps them in two families of calls).
template <typename GetIv, typename GetLog>
std::string infoLog(GLuint object, GetIv getIv, GetLog getLog) {
  GLint len = 0;
  getIv(object, GL_INFO_LOG_LENGTH, &len);
  std::vector<char> log(static_cast<size_t>(len > 1 ? len : 1), '\0');
  getLog(object, len, nullptr, log.data());
  return log.data();
}

GLuint compile(GLenum type, const char* source, const std::string& name) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    const std::string log = infoLog(shader, glGetShaderiv, glGetShaderInfoLog);
    glDeleteShader(shader);
    throw GlError(name + (type == GL_VERTEX_SHADER ? ": vertex" : ": fragment") +
                  " shader does not compile: " + log);
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
    const std::string log = infoLog(program, glGetProgramiv, glGetProgramInfoLog);
    glDeleteProgram(program);
    throw GlError(name + ": program does not link: " + log);
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
