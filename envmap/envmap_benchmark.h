// Timing of live lighting's per-frame stages (issue 16, "Speed"; Havran et al. 2005 §6 gives
// the paper's own: fisheye to polar map < 1 ms, CDF < 2 ms, 410 samples/ms, FIR 1 ms for 210
// lights, clustering 1 ms for 300), for `penumbra bench-envmap`. The input: synthetic fisheye
// frames (480 × 480, a sky and a window, 5% sensor noise) resampled to the 360 × 90 map; each
// stage is timed once per frame on one thread and the median over the frames is reported.
// Not a test: timings depend on the machine and its load. Built with OpenCV (cv::fisheye).
#pragma once

#include <cstdint>

namespace penumbra::envmap {

struct EnvmapBenchResult {
  uint32_t frames = 0, lights = 0, clusters = 0, supersample = 0;
  double resampleMs = 0;       // median: fisheye frame → hemisphere map (part of cdfMs)
  double resampleWarmMs = 0;   // median: the same with the frame already in the cache
  double cdfMs = 0;            // median: resampling + the map's CDFs and power
  double samplesPerMs = 0;     // lights / median time of sampling them
  double filterClusterMs = 0;  // median: FIR of the lights, then clustering into ≤ Q
  uint32_t clustersMade = 0;   // clusters of the last frame
};

// `supersample`² taps per map pixel in the fisheye resampling (FisheyeResampler).
EnvmapBenchResult benchEnvmap(uint32_t lights, uint32_t frames, uint32_t maxClusters,
                              uint32_t supersample = 2);

}  // namespace penumbra::envmap
