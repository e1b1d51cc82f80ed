#include "lighting/envmap_benchmark.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "core/clock.h"
#include "core/random.h"
#include "lighting/envmap_sampling.h"
#include "lighting/light_clustering.h"
#include "lighting/light_filter.h"

namespace penumbra::lighting {

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// A sky brighter at the zenith, a window, 5% per-pixel noise: frame `frame` of the input.
HemisphereMap benchFrame(uint64_t frame) {
  HemisphereMap map{core::ImageF(kEnvmapCols, kEnvmapRows)};
  for (uint32_t y = 0; y < kEnvmapRows; ++y)
    for (uint32_t x = 0; x < kEnvmapCols; ++x) {
      const float sky = 1.0f - 0.5f * float(y) / kEnvmapRows;
      const bool window = x >= 70 && x < 110 && y >= 40 && y < 60;
      const float base[3] = {window ? 40.0f : 0.6f * sky, window ? 36.0f : 0.8f * sky,
                             window ? 28.0f : sky};
      float* p = map.radiance.pixel(x, y);
      for (int c = 0; c < 3; ++c) {
        const uint64_t sample = (uint64_t(y) * kEnvmapCols + x) * 3 + c;
        p[c] = base[c] * float(1.0 + 0.05 * (2 * core::unitSample(frame, sample) - 1));
      }
    }
  return map;
}

}  // namespace

EnvmapBenchResult benchEnvmap(uint32_t lights, uint32_t frames, uint32_t maxClusters) {
  if (lights == 0 || frames == 0 || maxClusters == 0)
    throw std::invalid_argument("bench-envmap: lights, frames and clusters must be at least 1");
  const SamplePattern pattern(lights);
  std::vector<HemisphereMap> maps;
  for (uint32_t f = 0; f < std::min<uint32_t>(frames, 16); ++f) maps.push_back(benchFrame(f));
  TemporalLightFilter filter;
  std::vector<double> cdfMs, sampleMs, filterClusterMs;
  EnvmapBenchResult result;
  EnvmapDistribution distribution(maps[0], "bench frame");  // sized once, as a live loop does
  core::Stopwatch watch;
  for (uint32_t f = 0; f < frames; ++f) {
    const HemisphereMap& map = maps[f % maps.size()];
    watch.lap();
    distribution.update(map, "bench frame");
    cdfMs.push_back(watch.lap());
    const LightSet raw = distribution.sample(pattern, lights);
    sampleMs.push_back(watch.lap());
    const LightClusters clusters = clusterLights(filter.push(raw), maxClusters);
    filterClusterMs.push_back(watch.lap());
    result.clustersMade = uint32_t(clusters.lights.size());
  }
  result.frames = frames;
  result.lights = lights;
  result.clusters = maxClusters;
  result.cdfMs = median(cdfMs);
  result.samplesPerMs = lights / median(sampleMs);
  result.filterClusterMs = median(filterClusterMs);
  return result;
}

}  // namespace penumbra::lighting
