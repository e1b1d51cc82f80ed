// Small GL helpers shared by the coverage check and the trace replay (not installed).
#pragma once

#include <GLES3/gl3.h>

#include <string>

namespace penumbra::gl::detail {

// Compiles and links a GLSL ES 3.00 program; throws GlError with the info log.
GLuint buildProgram(const char* vertexSource, const char* fragmentSource, const std::string& name);

// Throws GlError if the bound draw framebuffer is incomplete.
void checkFramebuffer(const std::string& name);

}  // namespace penumbra::gl::detail
