// The per-frame loop of `penumbra render` for tools that measure it (`penumbra accuracy`,
// penumbra-accuracy-sweep): compose the frame, render it with the occlusion probes, and
// feed the measured occlusion to the next frame's graded transfers (docs/fig3.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "raster/renderer.h"
#include "shadow/frame_compositor.h"
#include "shadow/scene_bundle.h"

namespace penumbra::shadow {

struct FrameLoop {
  FrameLoop(const SceneBundle& bundle, uint32_t shadowMapSize, const raster::RenderOptions& o)
      : FrameLoop(bundle, optionsFor(shadowMapSize), o) {}
  FrameLoop(const SceneBundle& bundle, const CompositorOptions& c, const raster::RenderOptions& o)
      : compositor(bundle, c), renderer(bundle.view, o), rgba(bundle.background.size()) {}

  static CompositorOptions optionsFor(uint32_t shadowMapSize) {
    CompositorOptions c;
    c.shadowMapSize = shadowMapSize;
    return c;
  }
  void step(const ProductPose& pose, size_t passes) {
    compositor.compose(pose, passes, ++frameNumber, frame, stats);
    renderer.render(frame, rgba, compositor.probes(), masks, compositor.objectProbesFrom());
    compositor.observe(masks);
  }
  // A still product: the second frame uses the first one's measured occlusion, as
  // `penumbra render` does.
  void still(const ProductPose& pose, size_t passes) {
    step(pose, passes);
    step(pose, passes);
  }

  FrameCompositor compositor;
  raster::Renderer renderer;
  raster::FrameContent frame;
  CompositeStats stats;
  std::vector<uint8_t> rgba, masks;  // RGBA8 frame; occlusion masks of the probes
  uint32_t frameNumber = 0;
};

}  // namespace penumbra::shadow
