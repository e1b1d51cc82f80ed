// A headless OpenGL ES 3.0 context on Mesa (llvmpipe) through surfaceless EGL, for the
// external check of the rasterizer (bench/gl_replay). Rendering always goes to FBOs: the
// context has no window surface.
#pragma once

#include <stdexcept>
#include <string>

namespace penumbra::gl {

// Every failure to get a display, a GLES 3 context or a GL object: the message says which
// step failed and the EGL/GL error code.
class GlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Owns an EGL display and a GLES 3.0 context, current on the constructing thread.
// Display: EGL_PLATFORM_SURFACELESS_MESA via eglGetPlatformDisplayEXT when the client
// extension is there, else EGL_DEFAULT_DISPLAY. Throws GlError when neither yields a
// display that can make a GLES 3 context current without a surface.
class GlContext {
 public:
  GlContext();
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // GL_RENDERER / GL_VERSION strings, and which EGL display path was taken.
  const std::string& renderer() const { return renderer_; }
  const std::string& version() const { return version_; }
  const std::string& displayKind() const { return displayKind_; }

  // Throws GlError naming `what` if glGetError() reports an error.
  static void check(const char* what);

 private:
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  std::string renderer_, version_, displayKind_;
};

}  // namespace penumbra::gl
