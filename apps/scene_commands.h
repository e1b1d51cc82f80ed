// The showroom subcommands of `penumbra`:
//   precompute SCENE -o BUNDLE   scene file -> scene bundle (lighting/precompute.h)
//   render BUNDLE --pose X,Z[,YAW] (--passes N | --fps F) [--out] [--hash] [--trace]
//   profile BUNDLE --passes 1,5,10,... --csv out.csv [--plot out.png]
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

#include "shadow/scene_bundle.h"

#ifdef PENUMBRA_HAVE_LIGHTING
#include "lighting/precompute.h"
#endif

namespace penumbra::apps {

struct Command {
  CLI::App* app;
  std::function<int()> run;
};

std::vector<Command> addSceneCommands(CLI::App& app);

#ifdef PENUMBRA_HAVE_LIGHTING
// `penumbra precompute`'s work: the scene file loaded (its models' warnings to stderr), then
// the bundle precomputed with each stage announced on stderr. `proxyScale` > 0 simplifies
// every product's shadow proxies again to that share of the file's triangle counts
// (scene::scaleShadowProxies); 0 keeps them. Throws the loaders' errors, which name the file
// and the field.
shadow::SceneBundle precomputeScene(const std::string& scenePath,
                                    const lighting::PrecomputeOptions& options,
                                    std::vector<lighting::StageTiming>& timings,
                                    double proxyScale = 0);
#endif

// --pose "X,Y,Z" or "X,Y,Z,YAW": floor position X, Z and lift Y above the floor in metres,
// yaw in degrees. Throws std::invalid_argument naming the bad item.
shadow::ProductPose parsePose(const std::string& text, uint32_t product);

// The pose `--pose` and `--product` ask for: the bundle's start pose with either replaced
// (empty / negative: kept). Throws cli::UsageError for a product the bundle does not have.
shadow::ProductPose requestedPose(const shadow::SceneBundle& b, const std::string& pose,
                                  int product);

}  // namespace penumbra::apps
