#include "apps/accuracy_command.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#ifdef PENUMBRA_HAVE_METRICS
#include "apps/render_flags.h"
#include "apps/scene_commands.h"
#include "core/cli.h"
#include "core/json_reader.h"
#include "core/progress.h"
#include "core/replace_file.h"
#include "reference/accuracy.h"
#include "reference/settings_tuning.h"
#include "shadow/render_settings.h"
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
  int mapSize = 0;                                               // 0: the bundle's
  int fineProxyPasses = -1;                                      // -1: the bundle's
  double texelsPerShadowPixel = -1;                              // < 0: the bundle's
  std::vector<std::string> referenceBounds, referenceBoundsOut;  // lower, upper
  RenderFlags render;
  reference::AccuracyOptions options;

  int run() {
    options.render = toOptions(render);
    if (!referenceBounds.empty()) {
      if (options.referencePath.empty()) {
        throw cli::UsageError("--reference-bounds needs --reference");
      }
      options.referenceLowerPath = referenceBounds.at(0);
      options.referenceUpperPath = referenceBounds.at(1);
    }
    if (!referenceBoundsOut.empty()) {
      options.referenceLowerOut = referenceBoundsOut.at(0);
      options.referenceUpperOut = referenceBoundsOut.at(1);
    }
    options.accumulation = raster::parseAccumulation(accumulation, "--accumulation");
    options.perClusterShares = !singleShare;
    const shadow::SceneBundle bundle = shadow::loadBundle(bundlePath);
    // What the flags do not say, the bundle's settings do (as render and the kiosk use them).
    const shadow::RenderSettings& s = bundle.settings;
    options.shadowMapSize = mapSize != 0 ? uint32_t(mapSize) : s.shadowMapSize;
    // --fine-proxy-passes sets every product's; without it each product keeps the bundle's.
    if (fineProxyPasses >= 0) {
      options.fineProxyPasses = uint32_t(fineProxyPasses);
    } else {
      options.fineProxyPasses = s.fineProxyPasses;
      options.productFineProxyPasses = s.productFineProxyPasses;
    }
    options.areaPenumbrae = !hardPasses && s.areaPenumbrae;
    options.texelsPerShadowPixel =
        texelsPerShadowPixel >= 0 ? texelsPerShadowPixel : s.texelsPerShadowPixel;
    options.shafts.pruneFraction = s.pruneFraction;
    options.shafts.maxReceiversPerLeaf = s.receiversPerLeaf;
    if (!pose.empty() || product >= 0) options.pose = requestedPose(bundle, pose, product);
    const reference::AccuracyReport report =
        reference::measureAccuracy(bundle, options, [](const reference::AccuracyRow& r) {
          const reference::ImageComparison& c = r.comparison;
          std::printf(
              "passes %3d (%3u) ms %7.3f mean_abs_shadow %.3f p99 %u ssim %.5f psnr %.2f "
              "flip %.5f",
              r.passesAsked, r.passes, r.msPerFrame, c.masked->meanAbs, c.masked->p99Abs, c.ssim,
              c.frame.psnr, c.frame.flipMean);
          if (r.beyondBounds) {
            std::printf(" beyond_bounds %.3f p99 %u", r.beyondBounds->meanAbs,
                        r.beyondBounds->p99Abs);
          }
          std::printf("\n");
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

// `penumbra tune` (reference/settings_tuning.h).
struct TuneCommand {
  std::string bundlePath, out, report, chart, posesPath, heldOutPath;
  std::vector<double> maxError;  // mean abs [, p99 [, FLIP]]
  // Scene models tried (a scene file's): every combination of power share, emitter patch size,
  // receiver patch size, proxy scale and irradiance-volume scale; empty: the file's own.
  std::vector<double> powerShares, emitterPatchSizes, patchSizes, proxyScales, volumeScales;
  double fps = 0;
  RenderFlags render;
  // The shaft settings are tried around the grid's choice unless the flags say otherwise.
  reference::TuneOptions options = [] {
    reference::TuneOptions o;
    o.pruneFractions = {0.005, 0.01, 0.02, 0.05};
    o.receiversPerLeaf = {4, 8, 16};
    o.texelsPerShadowPixel = {2, 4, 8};
    return o;
  }();

  // One scene model: 0 keeps the scene file's own value.
  struct SceneModel {
    double powerShare = 0;
    double emitterPatchSize = 0;
    double patchSize = 0;
    double proxyScale = 0;
    double volumeScale = 0;
  };

  // A bundle, or a scene file (.json) precomputed here with precompute's defaults and the
  // scene model's overrides.
  shadow::SceneBundle loadInput(SceneModel model) const {
    if (!sceneInput()) return shadow::loadBundle(bundlePath);
#ifdef PENUMBRA_HAVE_LIGHTING
    std::vector<lighting::StageTiming> timings;
    lighting::PrecomputeOptions precompute;
    precompute.powerShare = model.powerShare;
    precompute.emitterPatchSize = model.emitterPatchSize;
    precompute.patchSize = model.patchSize;
    if (model.volumeScale > 0)
      precompute.volumeDims = lighting::scaledVolumeDims(model.volumeScale);
    return precomputeScene(bundlePath, precompute, timings, model.proxyScale);
#else
    (void)model;
    throw cli::UsageError(bundlePath +
                          ": this build cannot precompute a scene file (no "
                          "lighting); give a bundle");
#endif
  }

  bool sceneInput() const {
    return std::filesystem::path(bundlePath).extension() == ".json";
  }

  static void line(const char* what, const reference::TunedCandidate& c) {
    // One count, or one per product (RenderSettings::productFineProxyPasses).
    std::string fine = std::to_string(c.settings.fineProxyPasses);
    if (!c.settings.productFineProxyPasses.empty()) {
      fine = "[";
      for (size_t i = 0; i < c.settings.productFineProxyPasses.size(); ++i) {
        fine += (i ? "," : "") + std::to_string(c.settings.productFineProxyPasses[i]);
      }
      fine += "]";
    }
    std::printf(
        "%s: max_passes %u shadow_map_size %u fine_proxy_passes %s area_penumbrae %s "
        "prune_fraction %s receivers_per_leaf %u texels_per_shadow_pixel %s | board_ms %.2f "
        "worst_mean_abs %.3f meets %s\n",
        what, c.settings.maxPasses, c.settings.shadowMapSize, fine.c_str(),
        c.settings.areaPenumbrae ? "on" : "off",
        core::formatNumber(c.settings.pruneFraction).c_str(), c.settings.receiversPerLeaf,
        core::formatNumber(c.settings.texelsPerShadowPixel).c_str(), c.boardMs, c.worstMeanAbs,
        c.meets ? "yes" : "no");
  }

  // One scene model: its render settings searched (reference/settings_tuning.h).
  struct Model {
    SceneModel scene;
    shadow::SceneBundle bundle;
    reference::TuneReport report;
  };

  // The references of the last model made them: a model with the same photograph (another
  // power share keeps the room, its photograph, tone and products) measures against them.
  // Cutting the emitters finer changes the photograph a little (it is drawn from the
  // patches' radiance), and so does cutting the room's patches coarser or finer: such a model
  // makes its own. Other proxies and volumes change neither: the reference casts and shades
  // the product's own mesh.
  std::optional<reference::TuneReferences> references;
  std::vector<uint8_t> referencesBackground;

  static std::string describe(const SceneModel& s) {
    std::string d;
    if (s.powerShare > 0) d += "power share " + core::formatNumber(s.powerShare);
    if (s.emitterPatchSize > 0) {
      d += (d.empty() ? "" : ", ") + std::string("emitter patches ") +
           core::formatNumber(s.emitterPatchSize) + " m";
    }
    if (s.patchSize > 0) {
      d += (d.empty() ? "" : ", ") + std::string("patches ") + core::formatNumber(s.patchSize) +
           " m";
    }
    if (s.proxyScale > 0) {
      d += (d.empty() ? "" : ", ") + std::string("proxies x") + core::formatNumber(s.proxyScale);
    }
    if (s.volumeScale > 0) {
      d += (d.empty() ? "" : ", ") + std::string("volume x") + core::formatNumber(s.volumeScale);
    }
    return d;
  }

  Model tuneModel(SceneModel scene) {
    Model m{scene, loadInput(scene), {}};
    if (options.poses.empty()) options.poses = {{"start", m.bundle.startPose}};
    const auto progress = [](core::Progress& bar) {
      return [&bar](size_t done, size_t total, const std::string&) { bar.fraction(done, total); };
    };
    if (!references || referencesBackground != m.bundle.background) {
      core::Progress bar("references");
      references = reference::makeTuneReferences(m.bundle, options, progress(bar));
      referencesBackground = m.bundle.background;
      bar.finish();
    }
    core::Progress bar("tune");
    m.report = reference::tuneSettings(m.bundle, options, *references, progress(bar));
    bar.finish();
    if (const std::string d = describe(scene); !d.empty()) {
      std::printf("%s (%zu sources): ", d.c_str(), m.bundle.sets.sources.size());
    }
    std::printf("candidates %zu, poses %zu, held out %zu\n", m.report.candidates.size(),
                options.poses.size(), options.heldOut.size());
    line("defaults", m.report.defaults);
    if (m.report.chosen) line("chosen", m.report.candidates[*m.report.chosen]);
    return m;
  }

  int run() {
    options.measure.render = toOptions(render);
    options.target.meanAbs = maxError.at(0);
    if (maxError.size() > 1) options.target.p99 = maxError[1];
    if (maxError.size() > 2) options.target.flip = maxError[2];
    if (fps > 0) options.maxBoardMs = 1000.0 / fps;
    const bool sceneModels = !powerShares.empty() || !emitterPatchSizes.empty() ||
                             !patchSizes.empty() || !proxyScales.empty() || !volumeScales.empty();
    if (sceneModels && !sceneInput()) {
      const char* flag = !powerShares.empty()         ? "--power-shares"
                         : !emitterPatchSizes.empty() ? "--emitter-patch-sizes"
                         : !patchSizes.empty()        ? "--patch-sizes"
                         : !proxyScales.empty()       ? "--proxy-scales"
                                                      : "--volume-scales";
      throw cli::UsageError(std::string(flag) + " needs a scene file (.json): " + bundlePath +
                            "'s scene model is fixed");
    }
    if (!posesPath.empty()) options.poses = reference::loadPoseSet(posesPath);
    if (!heldOutPath.empty()) options.heldOut = reference::loadPoseSet(heldOutPath);
    // Scene models from the smallest (fewest sources: the smallest share, the largest
    // emitter patches; the largest receiver patches; the fewest proxy triangles) up: among
    // equal costs the first wins; the coarsest irradiance volume first, which costs the
    // frame nothing more or less (a product vertex looks it up in constant time), so the
    // smallest volume that meets the product's target is kept.
    auto values = [](std::vector<double> v, bool descending) {
      if (v.empty()) return std::vector<double>{0.0};
      std::sort(v.begin(), v.end());
      v.erase(std::unique(v.begin(), v.end()), v.end());
      if (descending) std::reverse(v.begin(), v.end());
      return v;
    };
    std::vector<Model> models;
    for (double share : values(powerShares, false)) {
      for (double emitter : values(emitterPatchSizes, true)) {
        for (double patches : values(patchSizes, true)) {
          for (double proxies : values(proxyScales, false)) {
            for (double volume : values(volumeScales, false)) {
              models.push_back(tuneModel({share, emitter, patches, proxies, volume}));
            }
          }
        }
      }
    }
    const Model* best = nullptr;
    for (const Model& m : models) {
      if (!m.report.chosen) continue;
      const double ms = m.report.candidates[*m.report.chosen].boardMs;
      if (!best || ms < best->report.candidates[*best->report.chosen].boardMs) best = &m;
    }
    if (!report.empty()) {
      nlohmann::json j;
      // A model's value is null where it keeps the scene file's own.
      auto orNull = [](double v) { return v > 0 ? nlohmann::json(v) : nlohmann::json(nullptr); };
      auto modelJson = [&](const SceneModel& m) {
        return nlohmann::json{{"power_share", orNull(m.powerShare)},
                              {"emitter_patch_size", orNull(m.emitterPatchSize)},
                              {"patch_size", orNull(m.patchSize)},
                              {"proxy_scale", orNull(m.proxyScale)},
                              {"volume_scale", orNull(m.volumeScale)}};
      };
      if (!sceneModels) {
        j = reference::toJson(options, models[0].report);
      } else {
        j = {{"scene_models", nlohmann::json::array()},
             {"chosen_scene_model", best ? modelJson(best->scene) : nullptr}};
        for (const Model& m : models) {
          nlohmann::json e = modelJson(m.scene);
          e["sources"] = m.bundle.sets.sources.size();
          e["tune"] = reference::toJson(options, m.report);
          j["scene_models"].push_back(std::move(e));
        }
      }
      core::writeFileReplacing(report, j.dump(2) + "\n");
    }
    const Model& shown = best ? *best : models.back();
    if (!chart.empty()) reference::writeParetoChart(chart, options, shown.report);
    if (!best) {
      throw std::runtime_error("no candidate meets the target at every pose within the budget; " +
                               out + " not written");
    }
    const reference::TunedCandidate& c = best->report.candidates[*best->report.chosen];
    if (sceneModels) {
      std::printf("chosen scene model: %s (%zu sources)\n", describe(best->scene).c_str(),
                  best->bundle.sets.sources.size());
    }
    if (!options.heldOut.empty()) {
      line("held-out defaults", best->report.heldOutDefaults);
      line("held-out chosen", best->report.heldOutChosen);
    }
    shadow::SceneBundle tuned = best->bundle;
    tuned.settings = c.settings;
    tuned.settings.tuned = true;
    shadow::saveBundle(tuned, out);
    std::printf("wrote %s\n", out.c_str());
    return 0;
  }
};

// The reference's flags, shared by accuracy and tune: the Penumbra stand-in or the ray
// tracer's sampling.
// The camera rays default to jittered over each pixel unless o.rays.pixelCentres is already
// set (tune's default), when the flag to turn them back is --jittered.
void addReferenceFlags(CLI::App* app, reference::AccuracyOptions& o) {
  app->add_option("--reference-map", o.referenceMapSize,
                  "map size of the Penumbra stand-in (area penumbrae need 512 or less)")
      ->check(cli::NumberRange(16, 8192))
      ->capture_default_str();
  app->add_flag("--penumbra-reference", o.penumbraReference,
                "reference = Penumbra itself (2048 map, every source a pass), not ray tracing "
                "(the only choice when built without the ray tracer)");
#ifdef PENUMBRA_HAVE_REFERENCE
  app->add_option("--spp", o.rays.samplesPerPixel, "ray-traced reference: samples per pixel")
      ->check(cli::NumberRange(1, 65536))
      ->capture_default_str();
  app->add_option("--light-samples", o.rays.lightSamples,
                  "ray-traced reference: shadow rays per point")
      ->check(cli::NumberRange(1, 65536))
      ->capture_default_str();
  if (o.rays.pixelCentres) {
    app->add_flag_callback(
        "--jittered", [&o] { o.rays.pixelCentres = false; },
        "ray-traced reference: camera rays jittered over each pixel, anti-aliased (default: "
        "every ray through the pixel centre, as Penumbra samples)");
  } else {
    app->add_flag("--pixel-centres", o.rays.pixelCentres,
                  "ray-traced reference: every camera ray through the pixel centre, as Penumbra "
                  "samples (default: jittered over the pixel, anti-aliased)");
  }
  app->add_flag("--point-lights", o.rays.pointLights,
                "ray-traced reference: every shadow ray aimed at its emitter's centre, as "
                "Penumbra's passes cast (the cost of point sources, docs/accuracy.md)");
  app->add_option("--bounces", o.rays.bounces, "ray-traced reference: indirect bounces")
      ->check(cli::NumberRange(0, 16))
      ->capture_default_str();
  app->add_option("--seed", o.rays.seed, "ray-traced reference: seed")->capture_default_str();
#endif
}

}  // namespace
#endif

std::vector<Command> addAccuracyCommands([[maybe_unused]] CLI::App& app) {
  std::vector<Command> commands;
#ifdef PENUMBRA_HAVE_METRICS
  auto cmd = std::make_shared<AccuracyCommand>();
  CLI::App* c =
      app.add_subcommand("accuracy", "ms/frame and error against a reference per pass count");
  c->add_option("BUNDLE", cmd->bundlePath, "scene bundle (penumbra precompute)")->required();
  cli::addNumberList(c, "--passes", cmd->options.passes, "pass counts, comma-separated", 0, 100000)
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
  c->add_option("--texels-per-shadow-pixel", cmd->texelsPerShadowPixel,
                "a shadow map per source cluster: texels per pixel of its shadow on screen, at "
                "most the frame's map (0: every pass at the frame's map; default: the bundle's "
                "settings)")
      ->check(cli::NumberRange(0.0, shadow::kMaxTexelsPerShadowPixel));
  c->add_option("--ppd", cmd->options.pixelsPerDegree, "FLIP viewing condition: pixels per degree")
      ->check(cli::NumberRange(1.0, 1000.0))
      ->capture_default_str();
  c->add_option("--reference-out", cmd->options.referenceOut, "write the reference used as PNG");
  c->add_option("--mask-out", cmd->options.maskOut, "write the shadow region used as PNG");
  c->add_option("--reference-bounds", cmd->referenceBounds,
                "LOWER.png,UPPER.png: the --reference image's bounds where the photograph's 8 "
                "bits leave it open (written by --reference-bounds-out); adds the error beyond "
                "them")
      ->delimiter(',')
      ->expected(2);
  c->add_option("--reference-bounds-out", cmd->referenceBoundsOut,
                "LOWER.png,UPPER.png: write the ray-traced reference's bounds")
      ->delimiter(',')
      ->expected(2);
  c->add_option("--frames-out", cmd->options.framesOut,
                "write each measured frame as PNG: F.png becomes F-<passes>.png");
  addReferenceFlags(c, cmd->options);
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

  auto tune = std::make_shared<TuneCommand>();
  tune->options.measure.rays.samplesPerPixel = 16;  // issue 15's targets are stated at 16 spp
  tune->options.measure.rays.pixelCentres = true;   // as the pose set was measured
  // The stand-in's maps at the largest size that keeps area penumbrae, which the candidates
  // have: a larger one casts hard edges and would count the penumbrae as error.
  tune->options.measure.referenceMapSize = raster::kMaxAreaPenumbraMapSize;
  CLI::App* t = app.add_subcommand(
      "tune", "The cheapest render settings whose frames meet an error target at every pose");
  t->add_option("INPUT", tune->bundlePath,
                "scene bundle (penumbra precompute), or a scene file (.json) to precompute first")
      ->required();
  t->add_option("--max-error", tune->maxError,
                "target in the shadow region: MEAN_ABS[,P99[,FLIP]] levels (p99 default 6, "
                "FLIP unchecked unless given)")
      ->delimiter(',')
      ->expected(1, 3)
      ->check(cli::NumberRange(0.0, 255.0))
      ->required();
  t->add_flag("--p99-beyond-bounds", tune->options.target.p99BeyondBounds,
              "judge p99 beyond the ray-traced reference's bounds (where the photograph's 8 "
              "bits leave it open, docs/reference.md), not against its midpoint");
  t->add_option("--fps", tune->fps, "frame budget on the Raspberry Pi 4 cost model")
      ->check(cli::NumberRange(1.0, 1000.0));
  t->add_option("--poses", tune->posesPath,
                "pose set to tune on (penumbra-poses JSON; default: the bundle's start pose)");
  t->add_option("--held-out", tune->heldOutPath, "pose set only measured, with the choice");
  t->add_option("-o,--out", tune->out, "the tuned bundle to write")->required();
  t->add_option("--report", tune->report, "write every candidate's errors and cost as JSON");
  t->add_option("--chart", tune->chart, "write the Pareto chart (cost against error) as PNG");
  cli::addNumberList(t, "--passes", tune->options.passCeilings,
                     "pass ceilings tried, comma-separated", 1, 257)
      ->capture_default_str();
  cli::addNumberList(t, "--maps", tune->options.mapSizes,
                     "shadow-map sizes tried, comma-separated (multiples of 16 in 64..4096)", 64,
                     4096)
      ->capture_default_str();
  cli::addNumberList(t, "--fine-proxy-passes", tune->options.fineProxyPasses,
                     "fine-proxy pass counts tried, comma-separated", 0, 257)
      ->capture_default_str();
  cli::addNumberList(
      t, "--power-shares", tune->powerShares,
      "scene models tried: source power shares (Gibson 2003 §4), comma-separated, each "
      "precomputed from the scene file INPUT; the cheapest model and settings that meet "
      "the target win",
      0.01, 1.0);
  cli::addNumberList(t, "--prune-fractions", tune->options.pruneFractions,
                     "shaft pruning fractions tried around the grid's choice (Gibson 2003 §6), "
                     "comma-separated",
                     0.0, shadow::kMaxPruneFraction)
      ->capture_default_str();
  cli::addNumberList(t, "--receivers-per-leaf", tune->options.receiversPerLeaf,
                     "receivers per shaft-hierarchy leaf tried around the grid's choice, "
                     "comma-separated",
                     1, int(shadow::kMaxReceiversPerLeaf))
      ->capture_default_str();
  cli::addNumberList(t, "--texels-per-shadow-pixel", tune->options.texelsPerShadowPixel,
                     "a shadow map per source cluster, tried around the choice: texels per "
                     "pixel of the cluster's shadow on screen, comma-separated (0: every pass at "
                     "the frame's map)",
                     0.0, shadow::kMaxTexelsPerShadowPixel)
      ->capture_default_str();
  cli::addNumberList(
      t, "--emitter-patch-sizes", tune->emitterPatchSizes,
      "scene models tried: emitters cut into patches of at most these sizes in metres, "
      "each patch a source, comma-separated, each precomputed from the scene file "
      "INPUT (with --power-shares: every pair)",
      0.02, 10.0);
  cli::addNumberList(t, "--patch-sizes", tune->patchSizes,
                     "scene models tried: the room's patches cut to at most these sizes in "
                     "metres (the scene file's finer regions, contact and shadow-boundary "
                     "patches kept), comma-separated",
                     0.02, 10.0);
  cli::addNumberList(
      t, "--proxy-scales", tune->proxyScales,
      "scene models tried: every product's shadow proxies simplified to these shares of the "
      "scene file's triangle counts, comma-separated (with the other scene-model flags: "
      "every combination)",
      0.01, 16.0);
  cli::addNumberList(t, "--volume-scales", tune->volumeScales,
                     "scene models tried: the irradiance volume's grid (20x10x20) times these "
                     "scales per axis, comma-separated; judge them with --max-product-error",
                     0.05, 8.0);
  t->add_option("--max-product-error", tune->options.target.productMeanAbs,
                "mean abs error over the product's own pixels (8-bit levels) every pose must "
                "also meet: its shading, which the irradiance volume gives (default: not "
                "checked)")
      ->check(cli::NumberRange(0.0, 255.0));
  t->add_option("--ppd", tune->options.measure.pixelsPerDegree,
                "FLIP viewing condition: pixels per degree")
      ->check(cli::NumberRange(1.0, 1000.0))
      ->capture_default_str();
  addReferenceFlags(t, tune->options.measure);
  addRenderFlags(t, tune->render);
  commands.push_back({t, [tune] { return tune->run(); }});
#endif
  return commands;
}

}  // namespace penumbra::apps
