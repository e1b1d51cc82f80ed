#include "envmap/envmap_benchmark.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "core/clock.h"
#include "core/random.h"
#include "envmap/envmap_sampling.h"
#include "envmap/fisheye_resampler.h"
#include "envmap/lat_long.h"
#include "envmap/light_clustering.h"
#include "envmap/light_filter.h"

namespace penumbra::envmap {

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// A sky brighter at the zenith and a window (a lat-long map), photographed through a
// 480 × 480 equidistant fisheye (the paper's VGA camera's image circle) with 5% per-pixel
// sensor noise: frame `frame` of the input. Eight such frames (22 MB) are cycled, so a frame
// is not in the cache when it is resampled.
core::ImageF benchFrame(const FisheyeLens& lens, uint64_t frame) {
  core::ImageF latLong(720, 360);
  for (uint32_t y = 0; y < latLong.height; ++y)
    for (uint32_t x = 0; x < latLong.width; ++x) {
      const float sky = 1.0f - 0.5f * float(y) / float(latLong.height);
      const bool window = x >= 140 && x < 220 && y >= 80 && y < 140;
      float* p = latLong.pixel(x, y);
      p[0] = window ? 40.0f : 0.6f * sky;
      p[1] = window ? 36.0f : 0.8f * sky;
      p[2] = window ? 28.0f : sky;
    }
  core::ImageF image = renderFisheye(latLong, lens);
  for (size_t i = 0; i < image.pixels.size(); ++i)
    image.pixels[i] *= float(1.0 + 0.05 * (2 * core::unitSample(frame, i) - 1));
  return image;
}

}  // namespace

EnvmapBenchResult benchEnvmap(uint32_t lights, uint32_t frames, uint32_t maxClusters,
                              uint32_t supersample) {
  if (lights == 0 || frames == 0 || maxClusters == 0 || supersample == 0)
    throw std::invalid_argument(
        "bench-envmap: lights, frames, clusters and taps must be at least 1");
  const SamplePattern pattern(lights);
  const FisheyeLens lens = FisheyeLens::equidistant180(480);
  const FisheyeResampler resampler(lens, kEnvmapCols, kEnvmapRows, supersample);
  std::vector<core::ImageF> images;
  for (uint32_t f = 0; f < std::min<uint32_t>(frames, 8); ++f)
    images.push_back(benchFrame(lens, f));
  HemisphereMap map;
  resampler.resample(images[0], map);
  EnvmapDistribution distribution(map, "bench frame");  // sized once, as a live loop does
  TemporalLightFilter filter;
  std::vector<double> resampleMs, resampleWarmMs, cdfMs, sampleMs, filterClusterMs;
  EnvmapBenchResult result;
  core::Stopwatch watch;
  for (uint32_t f = 0; f < frames; ++f) {
    watch.lap();
    resampler.resample(images[f % images.size()], map, "bench frame");
    resampleMs.push_back(watch.lap());
    distribution.update(map, "bench frame");
    cdfMs.push_back(resampleMs.back() + watch.lap());
    // Again, now that the frame is in the cache (as when the stage before, an EXR decode or an
    // HDR merge, has just written it).
    resampler.resample(images[f % images.size()], map, "bench frame");
    resampleWarmMs.push_back(watch.lap());
    const LightSet raw = distribution.sample(pattern, lights);
    sampleMs.push_back(watch.lap());
    const LightClusters clusters = clusterLights(filter.push(raw), maxClusters);
    filterClusterMs.push_back(watch.lap());
    result.clustersMade = uint32_t(clusters.lights.size());
  }
  result.resampleMs = median(resampleMs);
  result.resampleWarmMs = median(resampleWarmMs);
  result.frames = frames;
  result.lights = lights;
  result.supersample = supersample;
  result.clusters = maxClusters;
  result.cdfMs = median(cdfMs);
  result.samplesPerMs = lights / median(sampleMs);
  result.filterClusterMs = median(filterClusterMs);
  return result;
}

}  // namespace penumbra::envmap
