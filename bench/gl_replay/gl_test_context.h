// One headless GL context per test process, created on first use (never during test
// discovery). Tests GTEST_SKIP with the reason when Mesa/EGL cannot give one.
#pragma once

#include <cstdlib>
#include <memory>
#include <string>

#include "bench/gl_replay/gl_context.h"

namespace penumbra::gl::testing {

// Returns the context or nullptr with `why` set.
inline GlContext* sharedContext(std::string& why) {
  static std::string failure;
  static std::unique_ptr<GlContext> context = [] {
    // llvmpipe reads its thread count once; match the Renderer's 2 threads unless the
    // caller chose otherwise.
    setenv("LP_NUM_THREADS", "2", 0);
    try {
      return std::make_unique<GlContext>();
    } catch (const std::exception& e) {
      failure = e.what();
      return std::unique_ptr<GlContext>();
    }
  }();
  why = failure;
  return context.get();
}

}  // namespace penumbra::gl::testing

#define PENUMBRA_REQUIRE_GL()                                        \
  do {                                                               \
    std::string glWhy_;                                              \
    if (::penumbra::gl::testing::sharedContext(glWhy_) == nullptr) { \
      GTEST_SKIP() << "no OpenGL ES 3 context: " << glWhy_;          \
    }                                                                \
  } while (false)
