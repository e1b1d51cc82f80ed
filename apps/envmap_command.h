// `penumbra bench-envmap [--lights 300] [--frames 200] [--clusters 72]`: live lighting's
// per-frame stages timed (envmap/envmap_benchmark.h), one line per stage:
//   cdf_ms <median of fisheye resampling + CDF>
//   samples_per_ms <lights / median sampling time>
//   filter_cluster_ms <median>
// `penumbra envmap-sequence PROBE.exr -o DIR [--frames 48] [--size 160] [--animate ...]`: a
// lat-long light probe animated (envmap/probe_sequences.h: lamp-off, cloud, noise, flicker,
// rotate, still) and photographed through an equidistant 180° fisheye (renderFisheye), written
// as DIR/env_0000.exr ... in half float: the environment camera's footage for the virtual
// fisheye camera (firmware-sim/virtual_fisheye_camera.h). DIR must be absent or empty; the
// frames are written to a temporary folder beside it and renamed at the end.
// bench-envmap is present when built with OpenCV (the fisheye frames), envmap-sequence when
// also built with OpenEXR; otherwise they add nothing.
#pragma once

#include <vector>

#include "apps/scene_commands.h"

namespace penumbra::apps {

std::vector<Command> addEnvmapCommands(CLI::App& app);

}  // namespace penumbra::apps
