// The showroom subcommands of `penumbra`:
//   precompute SCENE -o BUNDLE   scene file -> scene bundle (lighting/precompute.h)
//   render BUNDLE --pose X,Z[,YAW] (--passes N | --fps F) [--out] [--hash] [--trace]
//   profile BUNDLE --passes 1,5,10,... --csv out.csv [--plot out.png]
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <vector>

namespace penumbra::apps {

struct Command {
  CLI::App* app;
  std::function<int()> run;
};

std::vector<Command> addSceneCommands(CLI::App& app);

}  // namespace penumbra::apps
