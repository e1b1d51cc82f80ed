// `penumbra bench-envmap [--lights 300] [--frames 200] [--clusters 72]`: live lighting's
// per-frame stages timed (envmap/envmap_benchmark.h), one line per stage:
//   cdf_ms <median of fisheye resampling + CDF>
//   samples_per_ms <lights / median sampling time>
//   filter_cluster_ms <median>
// Present when built with OpenCV (the fisheye frames); otherwise adds nothing.
#pragma once

#include <vector>

#include "apps/scene_commands.h"

namespace penumbra::apps {

std::vector<Command> addEnvmapCommands(CLI::App& app);

}  // namespace penumbra::apps
