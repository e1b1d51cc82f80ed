#include "apps/reference_commands.h"

#include "core/cli.h"
#include "core/progress.h"
#include "core/random.h"

#ifdef PENUMBRA_HAVE_REFERENCE
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "reference/differential.h"
#include "reference/reference_renderer.h"
#include "scene/image_io.h"
#include "shadow/scene_bundle.h"
#ifdef PENUMBRA_HAVE_OPENEXR
#include "lighting/exr_io.h"
#endif
#ifdef PENUMBRA_HAVE_SYNTH_SHOWROOM
#include "reference/synth_showroom.h"
#include "scene/scene_file.h"
#endif
#endif

namespace penumbra::apps {

#ifdef PENUMBRA_HAVE_REFERENCE
namespace {

// Progress on stderr (core/progress.h: redrawn on a terminal, plain lines in a log).
reference::ReferenceProgress progressBar(const char* label) {
  auto progress = std::make_shared<core::Progress>(label);
  return [progress](uint32_t done, uint32_t total) { progress->fraction(done, total); };
}

struct ReferenceCommand {
  std::string bundle, pose, out, exr, mask;
  int product = -1;
  bool noProduct = false, noise = false;
  reference::ReferenceOptions options;

  int run() const {
    const shadow::SceneBundle b = shadow::loadBundle(bundle);
    std::optional<shadow::ProductPose> placed;
    if (!noProduct) {
      placed = requestedPose(b, pose, product);
    }
    const reference::ReferenceScene scene = reference::referenceSceneOf(b, placed);
    const auto t0 = std::chrono::steady_clock::now();
    // L_noobj and L_obj are needed whole only for --exr; the frame needs their difference.
    reference::ReferenceOptions rendered = options;
    rendered.differenceOnly = exr.empty();
    const reference::ReferenceImage image =
        reference::renderReference(scene, rendered, progressBar("reference"));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const reference::DifferentialFrame frame =
        reference::composeDifferential(image, b.background, b.tone);
    if (placed) {
      std::printf("product %s at (%.3f, %.3f, %.3f) yaw %.1f\n",
                  b.products[placed->product].name.c_str(), double(placed->x), double(placed->lift),
                  double(placed->z), double(placed->yawDegrees));
    }
    std::printf("reference %ux%u spp %d light_samples %d bounces %d seconds %.2f\n", image.width,
                image.height, options.samplesPerPixel, options.lightSamples, options.bounces,
                seconds);
    std::printf("shadow_pixels %zu product_pixels %zu changed_pixels %zu\n", frame.shadowPixels,
                frame.objectPixels, reference::changedPixels(frame, b.background));
    if (noise) {
      // The same render with an unrelated seed: the two differ only by their Monte Carlo
      // noise (reference::shadowNoiseRms).
      reference::ReferenceOptions other = rendered;
      other.seed = core::splitmix64(options.seed ^ 0x4E4F495345ull);  // "NOISE"
      const reference::DifferentialFrame second = reference::composeDifferential(
          reference::renderReference(scene, other, progressBar("noise")), b.background, b.tone);
      size_t count = 0;
      const double rms = reference::shadowNoiseRms(frame, second, &count);
      std::printf("noise_rms_lsb_shadow %.3f (over %zu channel values)\n", rms, count);
    }
    if (!exr.empty()) {
#ifdef PENUMBRA_HAVE_OPENEXR
      // lighting::writeExr writes one RGB image per file: the final radiance to --exr,
      // L_noobj and L_obj beside it (ref.exr -> ref.noobj.exr, ref.obj.exr).
      const std::filesystem::path base(exr);
      auto sibling = [&](const char* tag) {
        std::filesystem::path p = base;
        p.replace_extension(std::string(".") + tag + base.extension().string());
        return p;
      };
      lighting::writeExr(base, reference::hdrImageOf(image.width, image.height, frame.radiance));
      lighting::writeExr(sibling("noobj"),
                         reference::hdrImageOf(image.width, image.height, image.noObject));
      lighting::writeExr(sibling("obj"),
                         reference::hdrImageOf(image.width, image.height, image.withObject));
#else
      throw cli::UsageError("--exr: this build has no OpenEXR (PENUMBRA_WITH_OPENEXR=OFF)");
#endif
    }
    scene::writePng(out, image.width, image.height, frame.rgba);
    if (!mask.empty()) {
      scene::writePng(mask, image.width, image.height, reference::shadowMaskRgba(frame));
    }
    return 0;
  }
};

#ifdef PENUMBRA_HAVE_SYNTH_SHOWROOM
struct SynthCommand {
  std::string scene, out, pose;
  int product = -1;
  reference::SynthOptions options;

  int run() const {
    const scene::SceneDescription sc = scene::loadSceneFile(scene);
    reference::SynthOptions o = options;
    if (!pose.empty() || product >= 0) {
      shadow::ProductPose p{static_cast<uint32_t>(sc.startPose.product),
                            static_cast<float>(sc.startPose.x), static_cast<float>(sc.startPose.z),
                            static_cast<float>(sc.startPose.yawDegrees), 0.0f};
      if (!pose.empty()) p = parsePose(pose, p.product);
      if (product >= 0) p.product = static_cast<uint32_t>(product);
      o.pose = p;
    }
    const auto t0 = std::chrono::steady_clock::now();
    reference::writeSynthShowroom(sc, o, out, progressBar("synth-showroom"));
    std::printf("synth-showroom %s -> %s (spp %d light_samples %d bounces %d) seconds %.2f\n",
                scene.c_str(), out.c_str(), o.render.samplesPerPixel, o.render.lightSamples,
                o.render.bounces,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    std::printf("capture manifest %s\n", (std::filesystem::path(out) / "capture.json").c_str());
    return 0;
  }
};
#endif

}  // namespace
#endif

std::vector<Command> addReferenceCommands([[maybe_unused]] CLI::App& app) {
  std::vector<Command> commands;
#ifdef PENUMBRA_HAVE_REFERENCE
  auto ref = std::make_shared<ReferenceCommand>();
  CLI::App* r = app.add_subcommand(
      "reference", "Ray-traced differential rendering of a product in the showroom (ground truth)");
  r->add_option("BUNDLE", ref->bundle, "scene bundle (penumbra precompute)")->required();
  r->add_option("--pose", ref->pose,
                "product position: X,Y,Z[,YAW_DEGREES] (Y: lift above the floor, metres)");
  r->add_option("--product", ref->product, "product index (default: the start pose's)");
  r->add_flag("--no-product", ref->noProduct, "render the empty room (I_final = background)");
  r->add_option("--spp", ref->options.samplesPerPixel, "jittered camera samples per pixel")
      ->check(cli::NumberRange(1, 65536))
      ->capture_default_str();
  r->add_option("--light-samples", ref->options.lightSamples,
                "shadow rays per surface point, over all emitting patches")
      ->check(cli::NumberRange(1, 65536))
      ->capture_default_str();
  r->add_flag("--pixel-centres", ref->options.pixelCentres,
              "every camera ray through the pixel centre, as Penumbra samples (default: "
              "jittered over the pixel, anti-aliased)");
  r->add_flag("--point-lights", ref->options.pointLights,
              "every shadow ray aimed at its emitter's centre, as Penumbra's passes cast "
              "(default: spread over each emitting patch)");
  r->add_option("--bounces", ref->options.bounces, "indirect bounces (path tracing)")
      ->check(cli::NumberRange(0, 16))
      ->capture_default_str();
  ref->options.threads = 2;
  r->add_option("--threads", ref->options.threads, "threads (the bytes do not depend on it)")
      ->check(cli::NumberRange(1, 256))
      ->capture_default_str();
  r->add_option("--seed", ref->options.seed, "random seed")->capture_default_str();
  r->add_option("--out", ref->out, "I_final as PNG")->required();
  r->add_option(
      "--exr", ref->exr,
      "float EXR of the final radiance; L_noobj, L_obj beside it as NAME.noobj.exr, NAME.obj.exr");
  r->add_option("--shadow-mask", ref->mask,
                "PNG, white where L_noobj - L_obj changes the 8-bit result");
  r->add_flag("--noise", ref->noise,
              "render twice with unrelated seeds and print the shadow region's noise in LSB");
  commands.push_back({r, [ref] { return ref->run(); }});
#endif
#ifdef PENUMBRA_HAVE_SYNTH_SHOWROOM
  auto syn = std::make_shared<SynthCommand>();
  CLI::App* sy = app.add_subcommand(
      "synth-showroom",
      "Path-trace a scene file into a capture with a known answer (brackets, probe, marks, "
      "object-present photograph, capture manifest)");
  sy->add_option("SCENE", syn->scene, "scene file (data/showroom/showroom.json)")->required();
  sy->add_option("--out", syn->out, "output folder (created)")->required();
  sy->add_option("--pose", syn->pose, "product in the object-present photograph: X,Y,Z[,YAW]");
  sy->add_option("--product", syn->product, "product index (default: the start pose's)");
  sy->add_option("--spp", syn->options.render.samplesPerPixel, "camera samples per pixel")
      ->check(cli::NumberRange(1, 65536))
      ->capture_default_str();
  sy->add_option("--light-samples", syn->options.render.lightSamples, "shadow rays per point")
      ->check(cli::NumberRange(1, 65536))
      ->capture_default_str();
  sy->add_option("--bounces", syn->options.render.bounces, "indirect bounces")
      ->check(cli::NumberRange(0, 16))
      ->capture_default_str();
  sy->add_option("--threads", syn->options.render.threads, "threads (same bytes for any)")
      ->check(cli::NumberRange(1, 256))
      ->capture_default_str();
  sy->add_option("--seed", syn->options.render.seed, "random seed")->capture_default_str();
  sy->add_option("--exposures", syn->options.exposures, "bracketed photographs (5..15)")
      ->capture_default_str();
  sy->add_option("--probe-size", syn->options.probeSize, "mirrored-ball image side (pixels)")
      ->capture_default_str();
  commands.push_back({sy, [syn] { return syn->run(); }});
#endif
  return commands;
}

}  // namespace penumbra::apps
