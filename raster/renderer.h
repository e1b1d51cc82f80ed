// The frame renderer: depth composite, shadow maps and mask-and-subtract passes of
// Gibson 2003 §7 (Fig. 2) on the CPU, bit-exact by docs/pipeline-spec.md.
//
// A Renderer is built once per StaticView (camera + room mesh): it snaps and bins the
// static mesh and renders its depth and triangle ids once (the kiosk camera is fixed).
// render() then draws any number of frames. Cost per frame: the shadow maps, plus only
// the pixels of the objects and of each pass's receiver triangles — never the full frame
// per pass.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "raster/frame_trace.h"
#include "simd/targets.h"

namespace penumbra::core {
class JobPool;
}

namespace penumbra::raster {

struct RenderOptions {
  simd::Isa isa = simd::Isa::kScalar;
  int threads = 1;    // 1..256; the result does not depend on it
  int tileSize = 32;  // 16, 32 or 64; the result does not depend on it
};

// Per-frame counters (filled by render()); they do not affect the pixels.
struct FrameStats {
  uint64_t shadowMapPixels = 0;  // covered shadow-map pixels, all passes
  // Occluder triangles drawn into the shadow maps, all passes: those left after back-face
  // culling and the viewport test (a fine proxy's passes draw more; issue 17's board cost).
  uint64_t shadowMapTriangles = 0;
  // The passes' shadow-map texels (each map's size squared), summed: what the maps' clearing
  // and summing costs grows with (the board's cost model; maps differ with a size per cluster).
  uint64_t shadowMapTexels = 0;
  uint64_t passPixels = 0;    // receiver pixels whose id matched, all passes
  uint64_t objectPixels = 0;  // object pixels that passed the depth test
  // Stage times: objects (setup, binning, composite), passes (shadow maps, S, masks),
  // finish (subtracting the sums, output).
  double msObjects = 0, msPasses = 0, msFinish = 0, msTotal = 0;
};

class Renderer {
 public:
  // Throws TraceError for an invalid view, std::invalid_argument for bad options
  // (unsupported ISA, threads < 1, tile size not 16/32/64).
  Renderer(const StaticView& view, const RenderOptions& options);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Draws `frame` into `rgbaOut` (width*height*4 bytes, row 0 at the top).
  // `frame` must be valid for this view (validateTrace); throws TraceError otherwise.
  void render(const FrameContent& frame, std::span<uint8_t> rgbaOut);

  // The same, also measuring occlusion at world-space `probes` (e.g. receiver vertices):
  // masks[p * passes + k] = 255 when pass k's shadow map occludes probe p (the binary test
  // of spec §7 at the point itself, from world space), else 0. Lets the caller estimate how
  // much light the product blocks where, for the next frame (docs/fig3.md). Probes from
  // index `objectProbesFrom` on lie on the objects themselves and use each pass's object bias.
  void render(const FrameContent& frame, std::span<uint8_t> rgbaOut,
              std::span<const core::Vec3> probes, std::vector<uint8_t>& masks,
              size_t objectProbesFrom = SIZE_MAX);

  const FrameStats& lastStats() const;
  const StaticView& view() const;
  // The renderer's worker threads (options.threads, the caller included), for the frame's
  // other per-vertex work between two render() calls (shadow::FrameLoop). Not during one.
  core::JobPool& pool();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Convenience: one frame of a trace into a new RGBA8 buffer.
std::vector<uint8_t> renderTrace(const FrameTrace& trace, const RenderOptions& options);

}  // namespace penumbra::raster
