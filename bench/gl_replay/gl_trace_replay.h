// Replays a frame trace through OpenGL ES 3.0 (Mesa llvmpipe on the test machines),
// mirroring docs/pipeline-spec.md §6–7 step by step, as an independent implementation of
// the same frame to compare bytes and speed with raster::Renderer.
//
// GL conventions used throughout (see gl_coverage.cpp for the coverage evidence):
//   * The vertex shader negates clip y, so GL window y equals our y-down window y and
//     GL framebuffer row r is our image row r. The read-back therefore needs no row
//     reversal: the picture is upside down in GL's own bottom-left convention, which is
//     exactly what makes llvmpipe's fill rule coincide with our top-left rule.
//   * Depth buffers are GL_DEPTH_COMPONENT32F (binary32 like ours), cleared to 1.0 (GL
//     clamps clear values to [0, 1]; ours are +inf, which only matters for z == 1).
//   * 8-bit attributes are interpolated linearly in screen space (spec §5) by passing
//     a·w and w and dividing per fragment: both are linear in clip space, so GL's
//     perspective-correct interpolation returns their screen-linear ratio exactly.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "raster/frame_trace.h"

namespace penumbra::gl {

// Host-side composition of spec §7 in binary64, rounded to binary32 (row-major):
// camera window (xw, yw y-down, zw) -> light texel (u, v row 0 at the top, depth).
// Throws std::invalid_argument if the camera matrix is singular.
core::Mat4 windowToLightTexel(const core::Mat4& camera, uint32_t width, uint32_t height,
                              const core::Mat4& light, uint32_t shadowMapSize);

// One GL renderer for one StaticView. Needs a current GlContext on the calling thread for
// its whole life. Throws GlError on any GL failure.
class GlTraceReplay {
 public:
  // `view` must be valid (loadTrace() validates).
  explicit GlTraceReplay(const raster::StaticView& view);
  ~GlTraceReplay();
  GlTraceReplay(const GlTraceReplay&) = delete;
  GlTraceReplay& operator=(const GlTraceReplay&) = delete;

  // Uploads the frame content (background, objects, occluders, receivers), draws it,
  // glFinish()es and reads it back into `rgbaOut` (width*height*4, row 0 at the top).
  // Static mesh vertices stay on the GPU side between frames, like the Renderer's cache.
  void render(const raster::FrameContent& frame, std::span<uint8_t> rgbaOut);

 private:
  struct ShadowTarget {
    uint32_t size = 0;
    unsigned texture = 0, fbo = 0;
  };
  void drawShadowMap(const raster::ShadowPass& pass, const core::Mesh& occluder,
                     ShadowTarget& target, int firstVertex);

  raster::StaticView view_;
  unsigned geometryProgram_ = 0, depthProgram_ = 0, passProgram_ = 0, backgroundProgram_ = 0;
  unsigned staticVao_ = 0, staticPositions_ = 0, staticIndices_ = 0;
  unsigned streamVao_ = 0, streamPositions_ = 0, streamAttributes_ = 0;
  unsigned emptyVao_ = 0;
  unsigned frameFbo_ = 0, frameColour_ = 0, frameDepth_ = 0, backgroundTexture_ = 0;
  std::vector<ShadowTarget> shadowTargets_;
  std::vector<float> positions_;     // per-frame de-indexed geometry, xyz
  std::vector<uint8_t> attributes_;  // rgb per vertex (colour or S)
};

}  // namespace penumbra::gl
