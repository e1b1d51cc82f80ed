#include "bench/gl_replay/gl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>

#include <cstdio>
#include <cstring>

namespace penumbra::gl {
namespace {

std::string hex(unsigned v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%04X", v);
  return buf;
}

bool hasExtension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
    const bool startOk = p == list || p[-1] == ' ';
    const bool endOk = p[n] == '\0' || p[n] == ' ';
    if (startOk && endOk) return true;
  }
  return false;
}

// Tries to initialise `dpy` and create a current, surfaceless GLES 3 context on it.
// Returns the context or nullptr with `why` filled in (the display is terminated then).
EGLContext makeContext(EGLDisplay dpy, std::string& why) {
  EGLint major = 0, minor = 0;
  if (eglInitialize(dpy, &major, &minor) != EGL_TRUE) {
    why = "eglInitialize failed (" + hex(static_cast<unsigned>(eglGetError())) + ")";
    return EGL_NO_CONTEXT;
  }
  const char* ext = eglQueryString(dpy, EGL_EXTENSIONS);
  if (!hasExtension(ext, "EGL_KHR_surfaceless_context")) {
    why = "display lacks EGL_KHR_surfaceless_context";
    eglTerminate(dpy);
    return EGL_NO_CONTEXT;
  }
  if (eglBindAPI(EGL_OPENGL_ES_API) != EGL_TRUE) {
    why = "eglBindAPI(EGL_OPENGL_ES_API) failed";
    eglTerminate(dpy);
    return EGL_NO_CONTEXT;
  }
  // EGL_KHR_no_config_context is not guaranteed; pick any ES3-renderable config.
  const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint count = 0;
  EGLConfig* configPtr = &config;
  if (eglChooseConfig(dpy, configAttribs, configPtr, 1, &count) != EGL_TRUE || count < 1) {
    configPtr = nullptr;  // fall back to EGL_NO_CONFIG_KHR (EGL_KHR_no_config_context)
    if (!hasExtension(ext, "EGL_KHR_no_config_context")) {
      why = "no EGL config with EGL_OPENGL_ES3_BIT";
      eglTerminate(dpy);
      return EGL_NO_CONTEXT;
    }
  }
  const EGLint ctxAttribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 0,
                               EGL_NONE};
  EGLContext ctx = eglCreateContext(dpy, configPtr ? config : nullptr, EGL_NO_CONTEXT, ctxAttribs);
  if (ctx == EGL_NO_CONTEXT) {
    why = "eglCreateContext(GLES 3.0) failed (" + hex(static_cast<unsigned>(eglGetError())) + ")";
    eglTerminate(dpy);
    return EGL_NO_CONTEXT;
  }
  if (eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx) != EGL_TRUE) {
    why = "eglMakeCurrent(surfaceless) failed (" + hex(static_cast<unsigned>(eglGetError())) + ")";
    eglDestroyContext(dpy, ctx);
    eglTerminate(dpy);
    return EGL_NO_CONTEXT;
  }
  return ctx;
}

}  // namespace

GlContext::GlContext() {
  std::string failures;
  EGLDisplay dpy = EGL_NO_DISPLAY;
  EGLContext ctx = EGL_NO_CONTEXT;

  const char* clientExt = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (hasExtension(clientExt, "EGL_MESA_platform_surfaceless") &&
      hasExtension(clientExt, "EGL_EXT_platform_base")) {
    auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (getPlatformDisplay != nullptr) {
      dpy = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      if (dpy == EGL_NO_DISPLAY) {
        failures += "surfaceless: eglGetPlatformDisplayEXT returned no display; ";
      } else {
        std::string why;
        ctx = makeContext(dpy, why);
        if (ctx != EGL_NO_CONTEXT)
          displayKind_ = "EGL_PLATFORM_SURFACELESS_MESA";
        else
          failures += "surfaceless: " + why + "; ";
      }
    } else {
      failures += "surfaceless: no eglGetPlatformDisplayEXT; ";
    }
  } else {
    failures += "surfaceless: EGL_MESA_platform_surfaceless not offered; ";
  }

  if (ctx == EGL_NO_CONTEXT) {
    dpy = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    if (dpy == EGL_NO_DISPLAY) {
      failures += "default display: eglGetDisplay returned no display";
    } else {
      std::string why;
      ctx = makeContext(dpy, why);
      if (ctx != EGL_NO_CONTEXT)
        displayKind_ = "EGL_DEFAULT_DISPLAY";
      else
        failures += "default display: " + why;
    }
  }
  if (ctx == EGL_NO_CONTEXT) {
    throw GlError("cannot create a headless OpenGL ES 3.0 context: " + failures);
  }
  display_ = dpy;
  context_ = ctx;
  auto str = [](GLenum e) {
    const auto* s = reinterpret_cast<const char*>(glGetString(e));
    return std::string(s != nullptr ? s : "?");
  };
  renderer_ = str(GL_RENDERER);
  version_ = str(GL_VERSION);
}

GlContext::~GlContext() {
  auto dpy = static_cast<EGLDisplay>(display_);
  eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(dpy, static_cast<EGLContext>(context_));
  eglTerminate(dpy);
}

void GlContext::check(const char* what) {
  const GLenum err = glGetError();
  if (err != GL_NO_ERROR) {
    throw GlError(std::string("OpenGL error ") + hex(err) + " in " + what);
  }
}

}  // namespace penumbra::gl
