// Pixel coverage of single snapped triangles as Mesa's rasterizer decides it, for the
// exact comparison with raster::coverageMask() (docs/pipeline-spec.md §4).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "bench/gl_replay/gl_context.h"
#include "raster/triangle_setup.h"

namespace penumbra::gl {

// How our y-down sub-pixel Y (row 0 at the top) is handed to GL, whose window origin is
// the bottom-left corner. kMirror: GL window y = H - Y/256 and the read-back rows are
// reversed; kDirect: GL window y = Y/256 and the rows are read back as they are (the
// picture is upside down in GL's own convention). kDirect reproduces our top-left rule on
// llvmpipe exactly, kMirror does not (horizontal-edge ties flip): see gl_coverage.cpp.
enum class YMapping : uint8_t { kMirror, kDirect };

// Draws triangles into a width x height RGBA8 FBO of the current context. The viewport is
// a power-of-two square up to 8x the image, centred on it (so Mesa does not clip
// triangles that stay within it), and NDC -> window coordinates is exact in binary32, so
// Mesa's snap to 1/256 px reproduces our integer vertices exactly.
class GlCoverage {
 public:
  // Requires a current context (GlContext). Throws GlError.
  GlCoverage(uint32_t width, uint32_t height, YMapping mapping);
  ~GlCoverage();
  GlCoverage(const GlCoverage&) = delete;
  GlCoverage& operator=(const GlCoverage&) = delete;

  // 1 where the triangle covers the pixel, row 0 at the top (our convention), W*H bytes.
  // Only x, y of the vertices are used; both windings are drawn (no culling).
  std::vector<uint8_t> mask(const std::array<raster::SnappedVertex, 3>& v);

 private:
  uint32_t width_, height_;
  YMapping mapping_;
  uint32_t viewportSide_ = 0;
  int32_t viewportOrigin_ = 0;
  unsigned program_ = 0, vao_ = 0, vbo_ = 0, fbo_ = 0, colour_ = 0;
  std::vector<uint8_t> pixels_;
};

}  // namespace penumbra::gl
