#include "shadow/frame_loop.h"

namespace penumbra::shadow {

void FrameLoop::step(const ProductPose& pose, size_t passes, std::span<const uint8_t> background) {
  run([&] { compositor.compose(pose, passes, ++frameNumber, frame, stats, background); });
}

void FrameLoop::step(const ProductPose& pose, std::span<const envmap::DirectionalLight> lights,
                     std::span<const uint8_t> background,
                     std::span<const envmap::DirectionalLight> fineLights) {
  run([&] {
    compositor.composeLit(pose, lights, ++frameNumber, frame, stats, background, fineLights);
  });
}

template <class Compose>
void FrameLoop::run(Compose compose) {
  const int64_t start = clock_.nowNanoseconds();
  compose();
  const int64_t composed = clock_.nowNanoseconds();
  // Linear accumulation's transfers do not depend on occlusion: no probes, nothing to observe.
  const bool measure = compositor.measuresOcclusion();
  if (measure) {
    renderer.render(frame, rgba, compositor.probes(), masks, compositor.objectProbesFrom());
  } else {
    renderer.render(frame, rgba);
  }
  const int64_t rendered = clock_.nowNanoseconds();
  if (measure) compositor.observe(masks);
  const int64_t end = clock_.nowNanoseconds();
  frameNs = end - start;

  stages = stats.stages;
  // compose()'s laps miss only their own bookkeeping: it goes to the frame content.
  int64_t composeStages = 0;
  for (int64_t ns : stages.ns) composeStages += ns;
  stages[FrameStage::kFrameContent] += (composed - start) - composeStages;
  const raster::FrameStats& r = renderer.lastStats();
  const auto toNs = [](double ms) { return static_cast<int64_t>(ms * 1e6); };
  stages[FrameStage::kRasterObjects] = toNs(r.msObjects);
  stages[FrameStage::kRasterPasses] = toNs(r.msPasses);
  stages[FrameStage::kRasterFinish] = (rendered - composed) - toNs(r.msObjects) - toNs(r.msPasses);
  stages[FrameStage::kObserve] = end - rendered;
}

void FrameLoop::step(const ProductPose& pose, const FrameRateController::Decision& decision,
                     std::span<const uint8_t> background) {
  compositor.setShadowMapSize(decision.shadowMapSize);
  step(pose, decision.passes, background);
}

}  // namespace penumbra::shadow
