#include "apps/accuracy_command.h"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#ifdef PENUMBRA_HAVE_METRICS
#include "apps/render_flags.h"
#include "apps/scene_commands.h"
#include "core/cli.h"
#include "reference/accuracy.h"
#endif

namespace penumbra::apps {

#ifdef PENUMBRA_HAVE_METRICS
namespace {

struct AccuracyCommand {
  std::string bundlePath, json, accumulation = "linear";
  std::string pose;  // empty: the start pose's
  int product = -1;  // -1: the pose's product
  bool singleShare = false;
  bool hardPasses = false;
  int mapSize = 0, referenceMap = 2048;  // mapSize 0: the bundle's
  int fineProxyPasses = -1;              // -1: the bundle's
  RenderFlags render;
  reference::AccuracyOptions options;

  int run() {
    options.render = toOptions(render);
    options.referenceMapSize = uint32_t(referenceMap);
    options.accumulation = raster::parseAccumulation(accumulation, "--accumulation");
    options.perClusterShares = !singleShare;
    const shadow::SceneBundle bundle = shadow::loadBundle(bundlePath);
    // What the flags do not say, the bundle's settings do (as render and the kiosk use them).
    const shadow::RenderSettings& s = bundle.settings;
    options.shadowMapSize = mapSize != 0 ? uint32_t(mapSize) : s.shadowMapSize;
    options.fineProxyPasses = fineProxyPasses >= 0 ? uint32_t(fineProxyPasses) : s.fineProxyPasses;
    options.areaPenumbrae = !hardPasses && s.areaPenumbrae;
    if (!pose.empty() || product >= 0) options.pose = requestedPose(bundle, pose, product);
    const reference::AccuracyReport report =
        reference::measureAccuracy(bundle, options, [](const reference::AccuracyRow& r) {
          const reference::ImageComparison& c = r.comparison;
          std::printf(
              "passes %3d (%3u) ms %7.3f mean_abs_shadow %.3f p99 %u ssim %.5f psnr %.2f "
              "flip %.5f\n",
              r.passesAsked, r.passes, r.msPerFrame, c.masked->meanAbs, c.masked->p99Abs, c.ssim,
              c.frame.psnr, c.frame.flipMean);
        });
    const nlohmann::json out = reference::toJson(bundlePath, options, report);
    if (json.empty()) {
      std::cout << out.dump(2) << "\n";
    } else {
      std::ofstream file(json);
      file << out.dump(2) << "\n";
      if (!file) throw std::runtime_error(json + ": cannot write JSON");
    }
    return 0;
  }
};

}  // namespace
#endif

std::vector<Command> addAccuracyCommands([[maybe_unused]] CLI::App& app) {
  std::vector<Command> commands;
#ifdef PENUMBRA_HAVE_METRICS
  auto cmd = std::make_shared<AccuracyCommand>();
  CLI::App* c =
      app.add_subcommand("accuracy", "ms/frame and error against a reference per pass count");
  c->add_option("BUNDLE", cmd->bundlePath, "scene bundle (penumbra precompute)")->required();
  c->add_option("--passes", cmd->options.passes, "pass counts, comma-separated")
      ->delimiter(',')
      ->check(cli::NumberRange::list(0, 100000))
      ->capture_default_str();
  c->add_option("--json", cmd->json, "write the JSON here instead of stdout");
  c->add_option("--pose", cmd->pose,
                "product position measured: X,Y,Z[,YAW_DEGREES] (Y: lift above the floor, "
                "metres); default: the bundle's start pose");
  c->add_option("--product", cmd->product, "product index (default: the start pose's)");
  c->add_option("--reference", cmd->options.referencePath,
                "reference image (PNG, the bundle's view size) at the measured pose");
  c->add_option("--mask", cmd->options.maskPath,
                "shadow-region mask PNG (default: from the reference)");
  c->add_option("--frames", cmd->options.frames, "timed frames per pass count (median)")
      ->check(cli::NumberRange(1, 10000))
      ->capture_default_str();
  c->add_option("--shadow-map", cmd->mapSize, "shadow-map size (default: the bundle's settings)")
      ->check(cli::NumberRange(16, 8192));
  c->add_option("--reference-map", cmd->referenceMap, "map size of the Penumbra stand-in")
      ->check(cli::NumberRange(16, 8192))
      ->capture_default_str();
  c->add_option("--ppd", cmd->options.pixelsPerDegree, "FLIP viewing condition: pixels per degree")
      ->check(cli::NumberRange(1.0, 1000.0))
      ->capture_default_str();
  c->add_option("--reference-out", cmd->options.referenceOut, "write the reference used as PNG");
  c->add_option("--mask-out", cmd->options.maskOut, "write the shadow region used as PNG");
  c->add_option("--frames-out", cmd->options.framesOut,
                "write each measured frame as PNG: F.png becomes F-<passes>.png");
  c->add_flag("--penumbra-reference", cmd->options.penumbraReference,
              "reference = Penumbra itself (2048 map, every source a pass), not ray tracing "
              "(the only choice when built without the ray tracer)");
#ifdef PENUMBRA_HAVE_REFERENCE
  c->add_option("--spp", cmd->options.rays.samplesPerPixel,
                "ray-traced reference: samples per pixel")
      ->check(cli::NumberRange(1, 65536))
      ->capture_default_str();
  c->add_option("--light-samples", cmd->options.rays.lightSamples,
                "ray-traced reference: shadow rays per point")
      ->check(cli::NumberRange(1, 65536))
      ->capture_default_str();
  c->add_flag("--pixel-centres", cmd->options.rays.pixelCentres,
              "ray-traced reference: every camera ray through the pixel centre, as Penumbra "
              "samples (default: jittered over the pixel, anti-aliased)");
  c->add_flag("--point-lights", cmd->options.rays.pointLights,
              "ray-traced reference: every shadow ray aimed at its emitter's centre, as "
              "Penumbra's passes cast (the cost of point sources, docs/accuracy.md)");
  c->add_option("--bounces", cmd->options.rays.bounces, "ray-traced reference: indirect bounces")
      ->check(cli::NumberRange(0, 16))
      ->capture_default_str();
  c->add_option("--seed", cmd->options.rays.seed, "ray-traced reference: seed")
      ->capture_default_str();
#endif
  c->add_option("--accumulation", cmd->accumulation,
                "how the passes are summed: linear (shares of the light, one shade-table "
                "lookup per pixel), fixed8_8 (1/256 levels, rounded once per pixel) or u8 "
                "(whole levels per pass)")
      ->check(CLI::IsMember({"u8", "fixed8_8", "linear"}))
      ->capture_default_str();
  c->add_flag("--single-share", cmd->singleShare,
              "graded transfers with one occluded share per vertex, not one per cluster");
  c->add_flag("--hard-passes", cmd->hardPasses,
              "every pass's shadow edge hard (2x2 PCF), as Gibson 2003 casts them, not spread "
              "over its light's penumbra (shadow/area_penumbra.h); also when the bundle's "
              "settings say so");
  c->add_option("--depth-bias", cmd->options.depthBias, "receivers' shadow-map depth bias")
      ->check(cli::NumberRange(0.0, 1.0))
      ->capture_default_str();
  c->add_option("--fine-proxy-passes", cmd->fineProxyPasses,
                "passes (the most energetic first) that draw the product's fine shadow proxy, "
                "when the bundle has one (default: the bundle's settings)")
      ->check(cli::NumberRange(0, 100000));
  c->add_option("--contact-radius", cmd->options.contactRadius,
                "contact band: shadow pixels this close to the product (pixels)")
      ->check(cli::NumberRange(1, 256))
      ->capture_default_str();
  addRenderFlags(c, cmd->render);
  commands.push_back({c, [cmd] { return cmd->run(); }});
#endif
  return commands;
}

}  // namespace penumbra::apps
