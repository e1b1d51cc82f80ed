#include "shadow/frame_runs.h"

#include <algorithm>
#include <stdexcept>

namespace penumbra::shadow {

FrameRateController::Options renderControllerOptions(double fps, const RenderSettings& settings) {
  if (!(fps > 0)) throw std::invalid_argument("frame rate must be positive");
  FrameRateController::Options o;
  o.targetFrameNs = static_cast<int64_t>(1e9 / fps);
  o.maxPasses = settings.maxPasses;
  o.initialPasses = std::min(8u, o.maxPasses);
  o.minPasses = std::min(4u, o.maxPasses);
  o.shadowMapSizes = shadowMapLadder(settings);  // below minPasses, smaller maps first
  return o;
}

FrameRateController::Decision settleFrameRate(FrameLoop& loop, const ProductPose& pose,
                                              const FrameRateController::Options& options,
                                              uint32_t frames, const FrameTimer& frameTimer) {
  FrameRateController controller(options);
  FrameRateController::Decision d;
  for (uint32_t f = 1; f <= frames; ++f) {
    d = controller.next();
    loop.step(pose, d);
    const int64_t frameNs = frameTimer ? frameTimer(loop) : loop.frameNs;
    controller.report(frameNs, d.passes, loop.renderer.lastStats().passPixels);
  }
  return d;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

PassProfile profilePasses(FrameLoop& loop, const ProductPose& pose, size_t passes, int frames) {
  PassProfile out;
  std::vector<double> total;
  total.reserve(size_t(frames));
  out.stages.reserve(size_t(frames));
  for (int f = 0; f < frames + 1; ++f) {
    ProductPose p = pose;
    p.x += 0.01f * float(f % 7);
    loop.step(p, passes);
    if (f == 0) continue;  // warm-up
    total.push_back(double(loop.frameNs) * 1e-6);
    out.stages.add(loop.stages);
  }
  out.passesAsked = passes;
  out.passes = loop.stats.passes;
  out.occludedSources = loop.stats.occludedSources;
  out.receivers = loop.stats.receiverPatches;
  out.shaftsVisited = loop.stats.shaftsVisited;
  out.shadowedPixels = loop.renderer.lastStats().passPixels;
  out.shadowMapTriangles = loop.renderer.lastStats().shadowMapTriangles;
  out.total = median(total);
  return out;
}

}  // namespace penumbra::shadow
