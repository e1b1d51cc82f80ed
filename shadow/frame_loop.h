// The per-frame loop (design §1, "Per frame"), the one every caller runs — `penumbra render`
// and `profile`, `penumbra accuracy`, penumbra-accuracy-sweep, the kiosk and with it the
// simulated board: compose the frame (FrameCompositor), render it with the occlusion probes
// (raster::Renderer), and feed the measured occlusion to the next frame's graded transfers
// (FrameCompositor::observe, docs/fig3.md). Frames are numbered 1, 2, ... (the §6.1 frame
// tags); the frame-rate controller's decisions (Gibson 2003 §8) set the shadow-map size and
// the pass count; the kiosk's camera frame can replace the bundle's photograph.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/clock.h"
#include "raster/renderer.h"
#include "shadow/frame_compositor.h"
#include "shadow/frame_rate_controller.h"
#include "shadow/scene_bundle.h"

namespace penumbra::shadow {

class FrameLoop {
 public:
  // `bundle` must outlive the loop.
  FrameLoop(const SceneBundle& bundle, uint32_t shadowMapSize, const raster::RenderOptions& o)
      : FrameLoop(bundle, optionsFor(shadowMapSize), o) {}
  FrameLoop(const SceneBundle& bundle, const CompositorOptions& c, const raster::RenderOptions& o)
      : compositor(bundle, c), renderer(bundle.view, o), rgba(bundle.background.size()) {
    // compose() and render() take turns, so the per-vertex stages borrow the renderer's
    // threads.
    compositor.setPool(&renderer.pool());
  }

  static CompositorOptions optionsFor(uint32_t shadowMapSize) {
    CompositorOptions c;
    c.shadowMapSize = shadowMapSize;
    return c;
  }

  // Frame frameNumber + 1 of the product at `pose` with at most `passes` clusters, into
  // `rgba`, over `background` (RGBA8 at the view's size, e.g. the kiosk's camera frame)
  // or, when it is empty, over the bundle's photograph.
  void step(const ProductPose& pose, size_t passes, std::span<const uint8_t> background = {});
  // The same with the frame-rate controller's decision: its shadow-map size from this frame
  // on, at most its number of passes.
  void step(const ProductPose& pose, const FrameRateController::Decision& decision,
            std::span<const uint8_t> background = {});
  // Live lighting (issue 16): the frame lit by the environment's distant lights, one pass
  // each (FrameCompositor::composeLit), at the shadow-map size last set.
  void step(const ProductPose& pose, std::span<const envmap::DirectionalLight> lights,
            std::span<const uint8_t> background = {},
            std::span<const envmap::DirectionalLight> fineLights = {});
  // A still product: the second frame uses the first one's measured occlusion, as
  // `penumbra render` does.
  void still(const ProductPose& pose, size_t passes) {
    step(pose, passes);
    step(pose, passes);
  }
  // The bundle's product `product` was given a new model (kiosk product files): placed and
  // shaded afresh in the next frame.
  void productModelChanged(uint32_t product) { compositor.productModelChanged(product); }

  FrameCompositor compositor;
  raster::Renderer renderer;
  raster::FrameContent frame;
  // The last frame's statistics (CompositeStats) and stage times on the steady clock:
  // placement to observe (the kiosk's own stages stay 0), summing to frameNs, the whole
  // step. The renderer's finish takes the rest of the render call (renderer.lastStats()
  // times objects and passes), so the stages add up.
  CompositeStats stats;
  FrameStages stages;
  int64_t frameNs = 0;
  std::vector<uint8_t> rgba, masks;  // RGBA8 frame; occlusion masks of the probes
  uint32_t frameNumber = 0;          // of the last frame; 0 before the first

 private:
  // compose() (one of the compositor's), render, observe, and the stage times.
  template <class Compose>
  void run(Compose compose);

  core::SteadyClock clock_;
};

}  // namespace penumbra::shadow
