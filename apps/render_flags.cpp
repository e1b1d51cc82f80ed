#include "apps/render_flags.h"

#include "core/cli.h"
#include "simd/targets.h"

namespace penumbra::apps {

void addRenderFlags(CLI::App* app, RenderFlags& flags) {
  app->add_option("--isa", flags.isa, "SIMD target: scalar|sse4|avx2|avx512|neon|best")
      ->capture_default_str();
  app->add_option("--threads", flags.threads, "worker threads (bytes do not depend on it)")
      ->check(cli::NumberRange(1, 256))
      ->capture_default_str();
  app->add_option("--tile", flags.tile, "tile side in pixels: 16, 32 or 64")
      ->check(CLI::IsMember({16, 32, 64}))
      ->capture_default_str();
}

raster::RenderOptions toOptions(const RenderFlags& flags) {
  raster::RenderOptions options;
  if (flags.isa == "best") {
    options.isa = simd::bestIsa();
  } else {
    const auto isa = simd::parseIsa(flags.isa);
    if (!isa) throw cli::UsageError("unknown --isa '" + flags.isa + "'");
    if (!simd::isSupported(*isa)) {
      throw cli::UsageError("--isa " + flags.isa + " is not supported here (see `penumbra isas`)");
    }
    options.isa = *isa;
  }
  options.threads = flags.threads;
  options.tileSize = flags.tile;
  return options;
}

}  // namespace penumbra::apps
