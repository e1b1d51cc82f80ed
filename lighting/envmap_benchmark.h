// Timing of live lighting's per-frame stages (issue 16, "Speed"; Havran et al. 2005 §6 gives
// the paper's own: CDF < 2 ms, 410 samples/ms, FIR 1 ms for 210 lights, clustering 1 ms for
// 300), for `penumbra bench-envmap`. The input is a sequence of synthetic 360 × 90 maps (a sky
// and a window, with per-pixel noise); each stage is timed once per frame on one thread and
// the median over the frames is reported. Not a test: timings depend on the machine and its
// load.
#pragma once

#include <cstdint>

namespace penumbra::lighting {

struct EnvmapBenchResult {
  uint32_t frames = 0, lights = 0, clusters = 0;
  double cdfMs = 0;            // median: the map's CDFs and power (EnvmapDistribution)
  double samplesPerMs = 0;     // lights / median time of sampling them
  double filterClusterMs = 0;  // median: FIR of the lights, then clustering into ≤ Q
  uint32_t clustersMade = 0;   // clusters of the last frame
};

EnvmapBenchResult benchEnvmap(uint32_t lights, uint32_t frames, uint32_t maxClusters);

}  // namespace penumbra::lighting
