// Runs of the per-frame loop (shadow::FrameLoop) longer than one still frame, as the tools
// make them: the frame-rate controller settling on this machine at a target rate (Gibson
// 2003 §8; `penumbra render --fps`), and the median stage times of a product that slides a
// little every frame, as on the kiosk, so that nothing is reused between frames (`penumbra
// profile`, `penumbra accuracy`). Cost: the frames they step, nothing more.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "shadow/frame_loop.h"
#include "shadow/frame_rate_controller.h"
#include "shadow/frame_stages.h"
#include "shadow/scene_bundle.h"

namespace penumbra::shadow {

// The controller `penumbra render --fps` uses: 8 passes to start, 4 to the bundle's pass
// ceiling (fewer when the ceiling is lower), and below 4 passes the bundle's map halved
// twice first (shadowMapLadder).
FrameRateController::Options renderControllerOptions(double fps, const RenderSettings& settings);

// The time a frame took, as the controller is told: the loop's measured wall time by
// default. Tests give a cost model instead, so that what they check does not depend on how
// busy the machine is.
using FrameTimer = std::function<int64_t(const FrameLoop&)>;

// Steps `loop` `frames` times at `pose` under a controller with `options`, reporting each
// frame's time (`frameTimer`, or the measured time when empty); returns the last frame's
// decision (the frame left in `loop`).
FrameRateController::Decision settleFrameRate(FrameLoop& loop, const ProductPose& pose,
                                              const FrameRateController::Options& options,
                                              uint32_t frames = 40,
                                              const FrameTimer& frameTimer = {});

// One pass count's cost. Counts are the last frame's; `total` is the median whole frame
// (ms) over the timed frames, `stages` every stage's times (FrameStages: their means add up
// to the mean frame).
struct PassProfile {
  size_t passesAsked = 0;
  uint32_t passes = 0, occludedSources = 0, receivers = 0, shaftsVisited = 0;
  uint64_t shadowedPixels = 0;      // receiver pixels the passes touched
  uint64_t shadowMapTriangles = 0;  // occluder triangles the passes drew (raster::FrameStats)
  double total = 0;
  FrameStageSamples stages;
};

// frames + 1 steps with at most `passes` passes, the product at pose.x + 0.01 * (f % 7) in
// frame f; frame 0 warms the caches and is not timed. frames >= 1.
PassProfile profilePasses(FrameLoop& loop, const ProductPose& pose, size_t passes, int frames);

// The median of `v` (the mean of the middle two for an even count); 0 when empty.
double median(std::vector<double> v);

}  // namespace penumbra::shadow
