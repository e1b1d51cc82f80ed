// The ground-truth subcommands of `penumbra` (issue 5; built when Embree is on):
//   reference BUNDLE [--pose X,Y,Z[,YAW]] [--product N] [--no-product] [--spp N]
//             [--light-samples N] [--bounces N] [--threads N] [--seed S] --out ref.png
//             [--exr ref.exr] [--shadow-mask mask.png] [--noise]
//   synth-showroom SCENE --out DIR [...]   (reference/synth_showroom.h)
// Without the reference library this adds nothing.
#pragma once

#include <CLI/CLI.hpp>
#include <vector>

#include "apps/scene_commands.h"

namespace penumbra::apps {

std::vector<Command> addReferenceCommands(CLI::App& app);

}  // namespace penumbra::apps
