#include "bench/gl_replay/gl_coverage.h"

#include <GLES3/gl3.h>

#include "bench/gl_replay/gl_util.h"

// How our coverage (spec §4) maps onto Mesa's, established empirically on llvmpipe
// (Mesa 22.3.6, LLVM 15) by gl_coverage_test.cpp over thousands of triangles:
//
// * Snapping. llvmpipe converts window coordinates to fixed point with 8 sub-pixel bits,
//   as we do. We hand it window coordinates that are exact multiples of
//   1/256 through a power-of-two viewport, so its snapped vertices are our integers.
//
// * y and the fill rule: YMapping::kDirect (GL window y = our Y / 256, no row reversal on
//   read-back) reproduces coverageMask() exactly; kMirror (GL's natural bottom-left
//   origin, rows reversed afterwards) does not. Why (inferred from the results): llvmpipe,
//   like D3D and our spec, applies a top-left rule in framebuffer-memory terms, where
//   "top" means the smallest window y, i.e. GL framebuffer row 0 (in GL's y-up view that
//   is a bottom-left rule, which the GL spec permits). With kDirect, GL row r is our row r, so GL's
//   top edges are ours (A = 0, B > 0 in spec §4) and its left edges are ours too (x is never
//   flipped). Mirroring y turns our horizontal top edges into llvmpipe's bottom edges, so
//   pixel centres exactly on a horizontal edge flip between the two triangles sharing it
//   (GlCoverage.MirroredMappingBreaksHorizontalEdgeTies). Left/right ties on sloped and
//   vertical edges are unaffected by a y mirror, which is why only horizontal-edge ties
//   showed up in the kMirror mismatches. Flipping y also reverses the winding; neither
//   side culls, and both normalise orientation first, so that does not matter.
//   Consequently the replay negates clip y in its vertex shader and reads rows back as
//   they are: GL's row 0 is our top row.
//
// * Clipping. llvmpipe clips triangles against the viewport volume before setup (no
//   guard band at this level): a triangle reaching outside the viewport gets new,
//   re-snapped vertices and edge pixels can move. Our coverageMask() never clips (spec §3
//   uses a 4x guard band upstream). So the viewport here is up to 8x larger than the image
//   and centred on it: the image is its window region [0, W) x [0, H), and only triangles
//   that leave [-3.5 S, 4.5 S] (S the image side rounded up to a power of two) would be
//   clipped. With a viewport equal to the image, 199 of 3000 random triangles reaching up to one
//   image side beyond it differed in one pixel or so; with the larger viewport none do.

namespace penumbra::gl {
namespace {

const char* const kVertex = R"(#version 300 es
layout(location = 0) in vec2 pos;
void main() { gl_Position = vec4(pos, 0.0, 1.0); }
)";

const char* const kFragment = R"(#version 300 es
precision highp float;
out vec4 colour;
void main() { colour = vec4(1.0); }
)";

uint32_t powerOfTwoAtLeast(uint32_t n) {
  uint32_t p = 1;
  while (p < n) p *= 2;
  return p;
}

}  // namespace

GlCoverage::GlCoverage(uint32_t width, uint32_t height, YMapping mapping)
    : width_(width),
      height_(height),
      mapping_(mapping),
      pixels_(static_cast<size_t>(width) * height * 4) {
  const uint32_t side = powerOfTwoAtLeast(width > height ? width : height);
  GLint maxViewport[2] = {0, 0};
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, maxViewport);
  const auto maxSide =
      static_cast<uint32_t>(maxViewport[0] < maxViewport[1] ? maxViewport[0] : maxViewport[1]);
  if (maxSide < side) throw GlError("GlCoverage: image larger than GL_MAX_VIEWPORT_DIMS");
  uint32_t factor = 8;
  while (factor > 1 && side * factor > maxSide) factor /= 2;
  viewportSide_ = side * factor;
  viewportOrigin_ = -static_cast<int32_t>(side * (factor - 1) / 2);
  program_ = detail::buildProgram(kVertex, kFragment, "coverage");
  glGenTextures(1, &colour_);
  glBindTexture(GL_TEXTURE_2D, colour_);
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, static_cast<GLsizei>(width),
                 static_cast<GLsizei>(height));
  glGenFramebuffers(1, &fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour_, 0);
  detail::checkFramebuffer("coverage FBO");
  glGenVertexArrays(1, &vao_);
  glBindVertexArray(vao_);
  glGenBuffers(1, &vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  glBufferData(GL_ARRAY_BUFFER, 6 * sizeof(float), nullptr, GL_STREAM_DRAW);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  GlContext::check("GlCoverage setup");
}

GlCoverage::~GlCoverage() {
  glDeleteBuffers(1, &vbo_);
  glDeleteVertexArrays(1, &vao_);
  glDeleteFramebuffers(1, &fbo_);
  glDeleteTextures(1, &colour_);
  glDeleteProgram(program_);
}

std::vector<uint8_t> GlCoverage::mask(const std::array<raster::SnappedVertex, 3>& v) {
  // Window = origin + (ndc + 1) * side / 2 with side a power of two and origin an integer:
  // every value below is a multiple of 2^-8 well inside 24 bits, so the casts, Mesa's
  // viewport transform and its 8-bit snap are exact and Mesa sees our integers unchanged.
  const double scale = 128.0 * viewportSide_;  // sub-pixel units per NDC unit
  const double origin = 256.0 * viewportOrigin_;
  float data[6];
  for (int i = 0; i < 3; ++i) {
    const double x = static_cast<double>(v[i].x);
    const double y = mapping_ == YMapping::kMirror ? 256.0 * height_ - static_cast<double>(v[i].y)
                                                   : static_cast<double>(v[i].y);
    data[2 * i] = static_cast<float>((x - origin) / scale - 1.0);
    data[2 * i + 1] = static_cast<float>((y - origin) / scale - 1.0);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(viewportOrigin_, viewportOrigin_, static_cast<GLsizei>(viewportSide_),
             static_cast<GLsizei>(viewportSide_));
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glClearColor(0, 0, 0, 0);
  glClear(GL_COLOR_BUFFER_BIT);
  glUseProgram(program_);
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  glBufferSubData(GL_ARRAY_BUFFER, 0, sizeof data, data);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, static_cast<GLsizei>(width_), static_cast<GLsizei>(height_), GL_RGBA,
               GL_UNSIGNED_BYTE, pixels_.data());
  GlContext::check("GlCoverage::mask");

  std::vector<uint8_t> out(static_cast<size_t>(width_) * height_);
  for (uint32_t row = 0; row < height_; ++row) {
    // GL row 0 is window y in [0, 1).
    const uint32_t ourRow = mapping_ == YMapping::kMirror ? height_ - 1 - row : row;
    const uint8_t* src = pixels_.data() + static_cast<size_t>(row) * width_ * 4;
    uint8_t* dst = out.data() + static_cast<size_t>(ourRow) * width_;
    for (uint32_t x = 0; x < width_; ++x) dst[x] = src[4 * x] != 0 ? 1 : 0;
  }
  return out;
}

}  // namespace penumbra::gl
