#include "shadow/frame_loop.h"

namespace penumbra::shadow {

void FrameLoop::step(const ProductPose& pose, size_t passes, std::span<const uint8_t> background) {
  const int64_t start = clock_.nowNanoseconds();
  compositor.compose(pose, passes, ++frameNumber, frame, stats);
  if (!background.empty()) frame.background.assign(background.begin(), background.end());
  renderer.render(frame, rgba, compositor.probes(), masks, compositor.objectProbesFrom());
  compositor.observe(masks);
  frameNs = clock_.nowNanoseconds() - start;
}

void FrameLoop::step(const ProductPose& pose, const FrameRateController::Decision& decision,
                     std::span<const uint8_t> background) {
  compositor.setShadowMapSize(decision.shadowMapSize);
  step(pose, decision.passes, background);
}

}  // namespace penumbra::shadow
