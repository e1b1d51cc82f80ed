#include "apps/accuracy_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#ifdef PENUMBRA_HAVE_METRICS
#include <nlohmann/json.hpp>

#include "apps/render_flags.h"
#include "core/image.h"
#include "raster/renderer.h"
#include "reference/image_metrics.h"
#include "reference/shadow_region.h"
#include "scene/image_io.h"
#include "shadow/frame_compositor.h"
#include "shadow/frame_loop.h"
#endif
#if defined(PENUMBRA_HAVE_METRICS) && defined(PENUMBRA_HAVE_REFERENCE)
#include "reference/differential.h"
#include "reference/reference_renderer.h"
#endif

namespace penumbra::apps {

#ifdef PENUMBRA_HAVE_METRICS
namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

void writeRgb(const std::string& path, const core::Image8& img) {
  std::vector<uint8_t> rgba(size_t(img.width) * img.height * 4, 255);
  for (size_t i = 0; i < size_t(img.width) * img.height; ++i) {
    for (size_t k = 0; k < 3; ++k) rgba[4 * i + k] = img.pixels[3 * i + k];
  }
  scene::writePng(path, img.width, img.height, rgba);
}

nlohmann::json orNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nullptr;
}

struct AccuracyCommand {
  std::string bundlePath, json, referencePath, maskPath;
  std::vector<int> passes{10, 20, 50};
  int frames = 5, mapSize = 256, referenceMap = 2048, referencePasses = 1000;
  double ppd = reference::FlipOptions{}.pixelsPerDegree;
  RenderFlags render;
  std::string referenceOut, maskOut;
  bool penumbraReference = false;  // the stand-in instead of rays (always without Embree)
  // The pipeline measured (shadow::CompositorOptions): accumulation, one occluded share per
  // vertex instead of per cluster, the receivers' depth bias and the contact band's radius.
  std::string accumulation = "fixed8_8";
  bool singleShare = false;
  float depthBias = shadow::CompositorOptions{}.depthBias;
  int contactRadius = 8;
#ifdef PENUMBRA_HAVE_REFERENCE
  reference::ReferenceOptions rays;
#endif

  int run() const {
    const raster::RenderOptions ro = toOptions(render);
    const shadow::SceneBundle bundle = shadow::loadBundle(bundlePath);
    const shadow::ProductPose pose = bundle.startPose;
    const uint32_t w = bundle.view.width, h = bundle.view.height;

    core::Image8 ref;
    nlohmann::json refInfo;
    core::Image8 mask;
    if (!referencePath.empty()) {
      ref = reference::loadRgb8(referencePath);
      refInfo = {{"kind", "image"}, {"file", referencePath}};
#ifdef PENUMBRA_HAVE_REFERENCE
    } else if (!penumbraReference) {
      // The ray-traced ground truth (reference/reference_renderer.h, docs/reference.md): HDR
      // differential rendering of the same room, light and placed product.
      const auto t0 = Clock::now();
      const reference::DifferentialFrame d = reference::composeDifferential(
          reference::renderReference(reference::referenceSceneOf(bundle, pose), rays),
          bundle.background, bundle.tone);
      ref = reference::fromRgba8(d.rgba, w, h, "ray-traced reference");
      if (maskPath.empty()) {
        // Its visible shadow: pixels the product's shadow changes, not the product itself.
        mask = core::Image8(w, h, 1, "ray-traced shadow mask");
        mask.pixels = d.shadowMask;
      }
      refInfo = {{"kind", "raytraced"},
                 {"spp", rays.samplesPerPixel},
                 {"light_samples", rays.lightSamples},
                 {"bounces", rays.bounces},
                 {"seed", rays.seed},
                 {"seconds", std::chrono::duration<double>(Clock::now() - t0).count()}};
#endif
    } else {
      shadow::FrameLoop r(bundle, uint32_t(referenceMap), ro);
      r.still(pose, size_t(referencePasses));
      ref = reference::fromRgba8(r.rgba, w, h, "penumbra reference");
      refInfo = {{"kind", "penumbra"},
                 {"passes", r.stats.passes},
                 {"shadow_map", referenceMap},
                 {"note", "stand-in for the ray-traced reference"}};
    }
    if (ref.width != w || ref.height != h) {
      throw reference::MetricsError(ref.name + ": size " + std::to_string(ref.width) + "x" +
                                    std::to_string(ref.height) + " differs from the bundle's " +
                                    std::to_string(w) + "x" + std::to_string(h) + " view");
    }
    shadow::CompositorOptions measured = shadow::FrameLoop::optionsFor(uint32_t(mapSize));
    measured.accumulation = raster::parseAccumulation(accumulation, "--accumulation");
    measured.perClusterShares = !singleShare;
    measured.depthBias = depthBias;
    shadow::FrameLoop zero(bundle, measured, ro);
    zero.still(pose, 0);
    if (!maskPath.empty()) {
      mask = reference::loadMask(maskPath);
    } else if (mask.pixels.empty()) {
      mask = reference::shadowRegion(ref, zero.rgba, bundle.background,
                                     "shadow region of the reference");
    }
    if (!referenceOut.empty()) writeRgb(referenceOut, ref);
    if (!maskOut.empty()) {
      std::vector<uint8_t> rgba(size_t(w) * h * 4, 255);
      for (size_t i = 0; i < size_t(w) * h; ++i) {
        for (size_t k = 0; k < 3; ++k) rgba[4 * i + k] = mask.pixels[i] ? 255 : 0;
      }
      scene::writePng(maskOut, w, h, rgba);
    }

    reference::CompareOptions co;
    co.flip.pixelsPerDegree = ppd;
    nlohmann::json rows = nlohmann::json::array();
    shadow::FrameLoop f(bundle, measured, ro);
    for (int n : passes) {
      std::vector<double> ms;
      for (int k = 0; k <= frames; ++k) {
        shadow::ProductPose p = pose;  // slides a little every frame, as in `profile`
        p.x += 0.01f * float(k % 7);
        f.step(p, size_t(n));
        if (k > 0) ms.push_back(double(f.frameNs) * 1e-6);
      }
      f.still(pose, size_t(n));
      const reference::ImageComparison c = reference::compareImages(
          ref, reference::fromRgba8(f.rgba, w, h, "penumbra " + std::to_string(n) + " passes"),
          &mask, co);
      const reference::RegionErrors& s = *c.masked;
      const reference::ContactErrors contact =
          reference::contactErrors(ref, f.rgba, zero.rgba, bundle.background, mask, contactRadius);
      rows.push_back({{"passes_asked", n},
                      {"passes", f.stats.passes},
                      {"ms_per_frame", median(ms)},
                      {"mean_abs_shadow", s.pixels ? nlohmann::json(s.meanAbs) : nullptr},
                      {"p99_abs_shadow", s.pixels ? nlohmann::json(s.p99Abs) : nullptr},
                      {"shadow_pixels", s.pixels},
                      {"mean_abs_frame", c.frame.meanAbs},
                      {"ssim", c.ssim},
                      {"psnr", orNull(c.frame.psnr)},
                      {"flip", c.frame.flipMean},
                      {"flip_shadow", s.pixels ? nlohmann::json(s.flipMean) : nullptr},
                      {"contact_pixels", contact.bandPixels},
                      {"mean_abs_contact", contact.meanAbs},
                      {"mean_signed_contact", contact.meanSigned},
                      {"spurious_shadow_pixels", contact.spuriousPixels}});
      std::printf(
          "passes %3d (%3u) ms %7.3f mean_abs_shadow %.3f p99 %u ssim %.5f psnr %.2f "
          "flip %.5f\n",
          n, f.stats.passes, median(ms), s.meanAbs, s.p99Abs, c.ssim, c.frame.psnr,
          c.frame.flipMean);
    }
    const nlohmann::json out = {{"bundle", bundlePath},
                                {"reference", refInfo},
                                {"shadow_map", mapSize},
                                {"flip_ppd", ppd},
                                {"width", w},
                                {"height", h},
                                {"frames_timed", frames},
                                {"results", rows},
                                {"accumulation", accumulation},
                                {"per_cluster_shares", !singleShare},
                                {"depth_bias", depthBias},
                                {"contact_radius", contactRadius}};
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
  CLI::App* c = app.add_subcommand(
      "accuracy", "ms/frame and error against a reference per pass count (issue 5)");
  c->add_option("BUNDLE", cmd->bundlePath, "scene bundle (penumbra precompute)")->required();
  c->add_option("--passes", cmd->passes, "pass counts, comma-separated")
      ->delimiter(',')
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  c->add_option("--json", cmd->json, "write the JSON here instead of stdout");
  c->add_option("--reference", cmd->referencePath,
                "reference image (PNG, the bundle's view size) at the start pose");
  c->add_option("--mask", cmd->maskPath, "shadow-region mask PNG (default: from the reference)");
  c->add_option("--frames", cmd->frames, "timed frames per pass count (median)")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  c->add_option("--shadow-map", cmd->mapSize, "shadow-map size")
      ->check(CLI::Range(16, 8192))
      ->capture_default_str();
  c->add_option("--reference-map", cmd->referenceMap, "map size of the Penumbra stand-in")
      ->check(CLI::Range(16, 8192))
      ->capture_default_str();
  c->add_option("--ppd", cmd->ppd, "FLIP viewing condition: pixels per degree")
      ->check(CLI::Range(1.0, 1000.0))
      ->capture_default_str();
  c->add_option("--reference-out", cmd->referenceOut, "write the reference used as PNG");
  c->add_option("--mask-out", cmd->maskOut, "write the shadow region used as PNG");
  c->add_flag("--penumbra-reference", cmd->penumbraReference,
              "reference = Penumbra itself (2048 map, every source a pass), not ray tracing "
              "(the only choice when built without the ray tracer)");
#ifdef PENUMBRA_HAVE_REFERENCE
  c->add_option("--spp", cmd->rays.samplesPerPixel, "ray-traced reference: samples per pixel")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  c->add_option("--light-samples", cmd->rays.lightSamples,
                "ray-traced reference: shadow rays per point")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  c->add_option("--bounces", cmd->rays.bounces, "ray-traced reference: indirect bounces")
      ->check(CLI::Range(0, 16))
      ->capture_default_str();
  c->add_option("--seed", cmd->rays.seed, "ray-traced reference: seed")->capture_default_str();
#endif
  c->add_option("--accumulation", cmd->accumulation,
                "how the passes are summed: fixed8_8 (1/256 levels, rounded once per pixel) "
                "or u8 (whole levels per pass)")
      ->check(CLI::IsMember({"u8", "fixed8_8"}))
      ->capture_default_str();
  c->add_flag("--single-share", cmd->singleShare,
              "graded transfers with one occluded share per vertex, not one per cluster");
  c->add_option("--depth-bias", cmd->depthBias, "receivers' shadow-map depth bias")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  c->add_option("--contact-radius", cmd->contactRadius,
                "contact band: shadow pixels this close to the product (pixels)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  addRenderFlags(c, cmd->render);
  commands.push_back({c, [cmd] { return cmd->run(); }});
#endif
  return commands;
}

}  // namespace penumbra::apps
