// Render options shared by the subcommands that draw frames.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "raster/renderer.h"

namespace penumbra::apps {

struct RenderFlags {
  std::string isa = "best";
  int threads = 1;
  int tile = 32;
};

// Adds --isa, --threads and --tile to `app`.
void addRenderFlags(CLI::App* app, RenderFlags& flags);

// Checks the flags against this CPU; throws std::invalid_argument with the reason.
raster::RenderOptions toOptions(const RenderFlags& flags);

}  // namespace penumbra::apps
