#include "apps/envmap_command.h"

#include <cstdio>
#include <memory>

#include "core/cli.h"
#ifdef PENUMBRA_HAVE_ENVMAP_BENCH
#include "envmap/envmap_benchmark.h"
#endif

namespace penumbra::apps {

#ifdef PENUMBRA_HAVE_ENVMAP_BENCH
namespace {

struct EnvmapBenchFlags {
  uint32_t lights = 300, frames = 200, clusters = 72, taps = 2;
};

int runEnvmapBench(const EnvmapBenchFlags& flags) {
  const envmap::EnvmapBenchResult r =
      envmap::benchEnvmap(flags.lights, flags.frames, flags.clusters, flags.taps);
  std::printf("map 360x90 lights %u frames %u clusters_max %u clusters_made %u threads 1\n",
              r.lights, r.frames, r.clusters, r.clustersMade);
  std::printf(
      "resample_ms %.4f (fisheye 480x480 -> map, %ux%u taps, frame not cached; in cdf_ms)\n",
      r.resampleMs, r.supersample, r.supersample);
  std::printf("resample_warm_ms %.4f (the same, frame already in the cache)\n", r.resampleWarmMs);
  std::printf("cdf_ms %.4f\n", r.cdfMs);
  std::printf("samples_per_ms %.0f\n", r.samplesPerMs);
  std::printf("filter_cluster_ms %.4f\n", r.filterClusterMs);
  return 0;
}

}  // namespace

std::vector<Command> addEnvmapCommands(CLI::App& app) {
  auto flags = std::make_shared<EnvmapBenchFlags>();
  CLI::App* cmd = app.add_subcommand(
      "bench-envmap", "Time live lighting's stages: CDF, sampling, FIR + clustering (medians)");
  cmd->add_option("--lights", flags->lights, "lights sampled per frame")
      ->check(cli::NumberRange(1, 100000))
      ->capture_default_str();
  cmd->add_option("--frames", flags->frames, "timed frames")
      ->check(cli::NumberRange(1, 100000))
      ->capture_default_str();
  cmd->add_option("--taps", flags->taps, "fisheye resampling: N x N taps per map pixel")
      ->check(cli::NumberRange(1, 8))
      ->capture_default_str();
  cmd->add_option("--clusters", flags->clusters, "at most this many clusters (Q)")
      ->check(cli::NumberRange(1, 100000))
      ->capture_default_str();
  return {{cmd, [flags] { return runEnvmapBench(*flags); }}};
}
#else
std::vector<Command> addEnvmapCommands(CLI::App&) {
  return {};
}
#endif

}  // namespace penumbra::apps
