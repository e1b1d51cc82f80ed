// `penumbra bench-envmap [--lights 300] [--frames 200] [--clusters 72]`: live lighting's
// per-frame stages timed (lighting/envmap_benchmark.h), one line per stage:
//   cdf_ms <median>
//   samples_per_ms <lights / median sampling time>
//   filter_cluster_ms <median>
#pragma once

#include <vector>

#include "apps/scene_commands.h"

namespace penumbra::apps {

std::vector<Command> addEnvmapCommands(CLI::App& app);

}  // namespace penumbra::apps
