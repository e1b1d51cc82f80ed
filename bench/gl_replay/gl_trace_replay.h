// Replays a frame trace through OpenGL ES 3.2 (Mesa llvmpipe on the test machines) as a
// second implementation of docs/pipeline-spec.md §6–7, to compare bytes and speed with
// raster::Renderer. GL rasterizes (coverage, per-pixel ordering, depth test, blending); the
// arithmetic GL would do its own way is done the spec's way:
//
//   * Geometry. Every triangle (room, objects, each pass's occluder, receivers) is
//     transformed, clipped (spec §3), snapped (§2) and set up (§4–5) on the CPU by
//     raster/triangle_setup.h, Penumbra's own functions. GL receives the snapped fan
//     triangles as exact multiples of 1/256 pixel through a power-of-two viewport (so its
//     8-bit snap sees our integers: gl_coverage.cpp), and per triangle, as flat attributes,
//     the spec's depth plane, plane origin, triangle id and 8.16 attribute planes.
//   * Per pixel, the fragment shader evaluates the spec's planes: depth in binary32 with
//     `precise` (no fused multiply-add, spec §1), colours and S in wrapping 32-bit integers
//     (§5). Depths are written as z / 2, so GL's depth clear value 1.0 stands for the
//     spec's +inf (§6) and the map's "+inf never occludes" (§7) is a comparison with 1.0.
//   * Ids. The room and the objects write their triangle ids (§6 steps 2–3) into an R32UI
//     attachment beside the depth; a receiver fragment is kept only where the id is its own
//     (step 4), so coplanar duplicates and clipped pieces subtract exactly once.
//   * The mask (§7) is computed in the shader from the texel values (texelFetch), exact
//     binary32 for u, v, d and integer weights for 2x2 PCF; the amount round(S·M/255) is
//     exact in integers and GL's reverse-subtract blend of unorm8 subtracts it with the
//     clamp at 0 (§6 step 4; passes commute, §8).
//
// What remains GL's own and where it could differ: docs/performance.md, "Where the GL replay
// cannot follow the spec".
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "raster/frame_trace.h"
#include "raster/triangle_setup.h"

namespace penumbra::gl {

// Spec §7's host composition in binary64 (raster/matrix4d.h: the Renderer's cofactor
// inverse and multiplication order), rounded to binary32, row-major: camera window (xw, yw
// y-down, zw) -> light texel (u, v row 0 at the top, depth).
// Throws std::invalid_argument if the camera matrix is singular.
core::Mat4 windowToLightTexel(const core::Mat4& camera, uint32_t width, uint32_t height,
                              const core::Mat4& light, uint32_t shadowMapSize);

// One GL renderer for one StaticView. Needs a current GlContext (OpenGL ES 3.2) on the
// calling thread for its whole life. Throws GlError on any GL failure.
class GlTraceReplay {
 public:
  // `view` must be valid (loadTrace() validates).
  explicit GlTraceReplay(const raster::StaticView& view);
  ~GlTraceReplay();
  GlTraceReplay(const GlTraceReplay&) = delete;
  GlTraceReplay& operator=(const GlTraceReplay&) = delete;

  // Sets up the frame content on the CPU (objects, occluders per pass, receivers), uploads
  // it with the background, draws, glFinish()es and reads the frame back into `rgbaOut`
  // (width*height*4, row 0 at the top). The room's set-up triangles stay on the GPU side
  // between frames, like the Renderer's static cache. Accumulation must be u8.
  void render(const raster::FrameContent& frame, std::span<uint8_t> rgbaOut);

  // One set-up triangle as GL receives it (three vertices each): exposed for the layout
  // checks of the tests. 17 four-byte words per vertex.
  struct Vertex {
    float x = 0, y = 0;                 // NDC of the snapped vertex in the viewport of its target
    float z00 = 0, dzdx = 0, dzdy = 0;  // spec §5 depth plane (flat)
    int32_t ox = 0, oy = 0;             // plane origin (flat)
    uint32_t id = 0;                    // triangle id of spec §6 (flat)
    uint32_t c[3] = {}, gx[3] = {}, gy[3] = {};  // 8.16 planes per channel (flat)
  };
  // Shadow-map triangles need the depth plane alone: 7 words a vertex.
  struct MapVertex {
    float x = 0, y = 0, z00 = 0, dzdx = 0, dzdy = 0;
    int32_t ox = 0, oy = 0;
  };

 private:
  struct Target {
    uint32_t side = 0;   // power-of-two viewport side, up to 8x the image
    int32_t origin = 0;  // viewport origin (both axes), <= 0
  };
  struct ShadowTarget {
    uint32_t size = 0;
    unsigned texture = 0, fbo = 0;
    Target viewport;
  };
  static Target targetFor(uint32_t width, uint32_t height);
  void emit(const raster::SetupTriangle& t, const Target& target, uint32_t id,
            const raster::AttributePlane* planes, std::vector<Vertex>& out) const;

  raster::StaticView view_;
  Target frameTarget_;
  unsigned mapProgram_ = 0, roomProgram_ = 0, objectProgram_ = 0, passProgram_ = 0;
  unsigned backgroundProgram_ = 0;
  unsigned staticVao_ = 0, staticBuffer_ = 0, streamVao_ = 0, streamBuffer_ = 0, emptyVao_ = 0;
  unsigned mapVao_ = 0, mapBuffer_ = 0;
  unsigned frameFbo_ = 0, passFbo_ = 0, frameColour_ = 0, frameIds_ = 0, frameDepth_ = 0;
  unsigned backgroundTexture_ = 0;
  int staticVertices_ = 0;
  std::vector<ShadowTarget> shadowTargets_;
  // The room's set-up triangles (spec §3–5), in index order: those of static triangle t are
  // staticSubs_[staticFirst_[t], staticFirst_[t + 1]).
  std::vector<raster::SetupTriangle> staticSubs_;
  std::vector<uint32_t> staticFirst_;
  std::vector<Vertex> stream_;        // per-frame vertices: objects, receivers
  std::vector<MapVertex> mapStream_;  // per-frame vertices: every pass's occluder
  std::vector<Vertex> scratch_;
  std::vector<raster::ClipVertex> clip_;
  std::vector<std::array<raster::SnappedVertex, 3>> fan_;
};

}  // namespace penumbra::gl
