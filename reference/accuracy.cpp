#include "reference/accuracy.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "scene/image_io.h"
#include "shadow/frame_loop.h"
#include "shadow/frame_runs.h"
#ifdef PENUMBRA_HAVE_REFERENCE
#include "reference/differential.h"
#endif

namespace penumbra::reference {
namespace {

using Clock = std::chrono::steady_clock;

void writeRgb(const std::string& path, const core::Image8& img) {
  std::vector<uint8_t> rgba(size_t(img.width) * img.height * 4, 255);
  for (size_t i = 0; i < size_t(img.width) * img.height; ++i) {
    for (size_t k = 0; k < 3; ++k) rgba[4 * i + k] = img.pixels[3 * i + k];
  }
  scene::writePng(path, img.width, img.height, rgba);
}

void writeMask(const std::string& path, const core::Image8& mask) {
  std::vector<uint8_t> rgba(size_t(mask.width) * mask.height * 4, 255);
  for (size_t i = 0; i < size_t(mask.width) * mask.height; ++i) {
    for (size_t k = 0; k < 3; ++k) rgba[4 * i + k] = mask.pixels[i] ? 255 : 0;
  }
  scene::writePng(path, mask.width, mask.height, rgba);
}

// "dir/f.png", 50 -> "dir/f-50.png"; a name without ".png" gets "-50.png".
std::string framePath(const std::string& pattern, int passes) {
  const bool png = pattern.size() >= 4 && pattern.compare(pattern.size() - 4, 4, ".png") == 0;
  std::string out(pattern, 0, png ? pattern.size() - 4 : pattern.size());
  out += '-';
  out += std::to_string(passes);
  out += ".png";
  return out;
}

nlohmann::json orNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nullptr;
}

// The reference image and, from the ray tracer, its own shadow mask (else left empty) and
// bounds (with the image's, when given).
core::Image8 makeReference(const shadow::SceneBundle& bundle, const AccuracyOptions& o,
                           const shadow::ProductPose& pose, nlohmann::json& info,
                           [[maybe_unused]] core::Image8& mask, core::Image8& lower,
                           core::Image8& upper) {
  const uint32_t w = bundle.view.width, h = bundle.view.height;
  if (o.referenceLowerPath.empty() != o.referenceUpperPath.empty()) {
    throw MetricsError("the reference's bounds need both images, lower and upper");
  }
  if (!o.referencePath.empty()) {
    info = {{"kind", "image"}, {"file", o.referencePath}};
    if (!o.referenceLowerPath.empty()) {
      lower = loadRgb8(o.referenceLowerPath);
      upper = loadRgb8(o.referenceUpperPath);
      info["lower"] = o.referenceLowerPath;
      info["upper"] = o.referenceUpperPath;
    }
    return loadRgb8(o.referencePath);
  }
  if (!o.referenceLowerPath.empty()) {
    throw MetricsError(o.referenceLowerPath + ": bounds are read with a reference image only");
  }
#ifdef PENUMBRA_HAVE_REFERENCE
  if (!o.penumbraReference) {
    // The ray-traced ground truth (reference/reference_renderer.h, docs/reference.md): HDR
    // differential rendering of the same room, light and placed product.
    const auto t0 = Clock::now();
    ReferenceOptions rays = o.rays;
    rays.differenceOnly = true;  // the frame is all that is used
    const DifferentialFrame d = composeDifferential(
        renderReference(referenceSceneOf(bundle, pose), rays), bundle.background, bundle.tone);
    // Its visible shadow: pixels the product's shadow changes, not the product itself.
    mask = core::Image8(w, h, 1, "ray-traced shadow mask");
    mask.pixels = d.shadowMask;
    lower = fromRgba8(d.lower, w, h, "ray-traced reference's lower bound");
    upper = fromRgba8(d.upper, w, h, "ray-traced reference's upper bound");
    info = {{"kind", "raytraced"},
            {"spp", o.rays.samplesPerPixel},
            {"light_samples", o.rays.lightSamples},
            {"pixel_centres", o.rays.pixelCentres},
            {"point_lights", o.rays.pointLights},
            {"bounces", o.rays.bounces},
            {"seed", o.rays.seed},
            {"seconds", std::chrono::duration<double>(Clock::now() - t0).count()}};
    return fromRgba8(d.rgba, w, h, "ray-traced reference");
  }
#endif
  shadow::FrameLoop r(bundle, o.referenceMapSize, o.render);
  // Every source its own pass, up to the frame's limit (a skylight can have more sources).
  r.still(pose, std::min(o.referencePasses, raster::kMaxPasses));
  info = {{"kind", "penumbra"},
          {"passes", r.stats.passes},
          {"shadow_map", o.referenceMapSize},
          {"note", "stand-in for the ray-traced reference"}};
  return fromRgba8(r.rgba, w, h, "penumbra reference");
}

}  // namespace

bool accuracyHasRayTracer() {
#ifdef PENUMBRA_HAVE_REFERENCE
  return true;
#else
  return false;
#endif
}

shadow::ProductPose measuredPose(const shadow::SceneBundle& bundle, const AccuracyOptions& o) {
  const shadow::ProductPose pose = o.pose.value_or(bundle.startPose);
  if (pose.product >= bundle.products.size()) {
    throw std::invalid_argument("product " + std::to_string(pose.product) + ": the bundle has " +
                                std::to_string(bundle.products.size()) + " products");
  }
  return pose;
}

namespace {

void checkViewSize(const core::Image8& img, uint32_t w, uint32_t h) {
  if (img.width != w || img.height != h) {
    throw MetricsError(img.name + ": size " + std::to_string(img.width) + "x" +
                       std::to_string(img.height) + " differs from the bundle's " +
                       std::to_string(w) + "x" + std::to_string(h) + " view");
  }
}

shadow::CompositorOptions measuredOptions(const AccuracyOptions& o) {
  shadow::CompositorOptions measured = shadow::FrameLoop::optionsFor(o.shadowMapSize);
  measured.accumulation = o.accumulation;
  measured.perClusterShares = o.perClusterShares;
  measured.depthBias = o.depthBias;
  measured.fineProxyPasses = o.fineProxyPasses;
  measured.productFineProxyPasses = o.productFineProxyPasses;
  measured.areaPenumbrae = o.areaPenumbrae;
  measured.texelsPerShadowPixel = o.texelsPerShadowPixel;
  measured.shafts = o.shafts;
  return measured;
}

}  // namespace

PoseReference makePoseReference(const shadow::SceneBundle& bundle, const AccuracyOptions& o,
                                const shadow::ProductPose& pose) {
  const uint32_t w = bundle.view.width, h = bundle.view.height;
  PoseReference r;
  r.image = makeReference(bundle, o, pose, r.info, r.region, r.lower, r.upper);
  checkViewSize(r.image, w, h);
  if (!r.lower.pixels.empty()) {
    checkViewSize(r.lower, w, h);
    checkViewSize(r.upper, w, h);
  }
  // Bounds that do not hold their own reference belong to another one.
  for (size_t i = 0; !r.lower.pixels.empty() && i < r.image.pixels.size(); ++i) {
    if (r.lower.pixels[i] > r.image.pixels[i] || r.image.pixels[i] > r.upper.pixels[i]) {
      throw MetricsError(r.image.name + ": outside its bounds " + r.lower.name + " and " +
                         r.upper.name + " at pixel (" + std::to_string(i / 3 % w) + ", " +
                         std::to_string(i / 3 / w) + ")");
    }
  }
  // The shadow-free frame (background + product): the region rule's and contact band's base.
  shadow::FrameLoop zero(bundle, measuredOptions(o), o.render);
  zero.still(pose, 0);
  r.unshadowed = zero.rgba;
  if (!o.maskPath.empty()) {
    r.region = loadMask(o.maskPath);
  } else if (r.region.pixels.empty()) {
    r.region =
        shadowRegion(r.image, r.unshadowed, bundle.background, "shadow region of the reference");
  }
  // A given or ray-traced mask leaves out the reference's product pixels only; where the
  // rasterized product covers a pixel the ray-traced one misses (its silhouette, its base on
  // the floor) the difference is the product's, not the shadow's: the region rule
  // (reference/shadow_region.h) leaves out Penumbra's product pixels too.
  excludeProductPixels(r.region, r.unshadowed, bundle.background);
  r.productRegion = core::Image8(bundle.view.width, bundle.view.height, 1, "product pixels");
  r.productRegion.pixels =
      productPixels(r.unshadowed, bundle.background, bundle.view.width, bundle.view.height);
  return r;
}

AccuracyReport measureAccuracy(const shadow::SceneBundle& bundle, const AccuracyOptions& o,
                               const std::function<void(const AccuracyRow&)>& onRow) {
  const shadow::ProductPose pose = measuredPose(bundle, o);
  const uint32_t w = bundle.view.width, h = bundle.view.height;
  AccuracyReport report;
  report.width = w;
  report.height = h;
  const PoseReference reference = makePoseReference(bundle, o, pose);
  report.reference = reference.info;
  const core::Image8& ref = reference.image;
  const core::Image8& mask = reference.region;
  if (!o.referenceOut.empty()) writeRgb(o.referenceOut, ref);
  if (!o.maskOut.empty()) writeMask(o.maskOut, mask);
  if (!o.referenceLowerOut.empty() || !o.referenceUpperOut.empty()) {
    if (reference.lower.pixels.empty()) {
      throw MetricsError("the reference (" + ref.name + ") has no bounds to write");
    }
    if (!o.referenceLowerOut.empty()) writeRgb(o.referenceLowerOut, reference.lower);
    if (!o.referenceUpperOut.empty()) writeRgb(o.referenceUpperOut, reference.upper);
  }
  const shadow::CompositorOptions measured = measuredOptions(o);

  CompareOptions co;
  co.flip.pixelsPerDegree = o.pixelsPerDegree;
  shadow::FrameLoop f(bundle, measured, o.render);
  for (int n : o.passes) {
    // Timed with the product sliding a little every frame, as in `penumbra profile`.
    const double ms = shadow::profilePasses(f, pose, size_t(n), o.frames).total;
    f.still(pose, size_t(n));
    AccuracyRow row;
    row.passesAsked = n;
    row.passes = f.stats.passes;
    row.msPerFrame = ms;
    const core::Image8 frame = fromRgba8(f.rgba, w, h, "penumbra " + std::to_string(n) + " passes");
    if (!o.framesOut.empty()) writeRgb(framePath(o.framesOut, n), frame);
    row.comparison = compareImages(ref, frame, &mask, co);
    row.contact =
        contactErrors(ref, f.rgba, reference.unshadowed, bundle.background, mask, o.contactRadius);
    if (!reference.lower.pixels.empty()) {
      row.beyondBounds = intervalErrors(reference.lower, reference.upper, frame, mask);
    }
    if (onRow) onRow(row);
    report.rows.push_back(std::move(row));
  }
  return report;
}

nlohmann::json toJson(const std::string& bundlePath, const AccuracyOptions& o,
                      const AccuracyReport& report) {
  nlohmann::json pose = nullptr;  // the start pose
  if (o.pose) {
    pose = {{"product", o.pose->product},
            {"x", o.pose->x},
            {"lift", o.pose->lift},
            {"z", o.pose->z},
            {"yaw_deg", o.pose->yawDegrees}};
  }
  nlohmann::json rows = nlohmann::json::array();
  for (const AccuracyRow& r : report.rows) {
    const ImageComparison& c = r.comparison;
    const RegionErrors& s = *c.masked;
    const RegionErrors* beyond = r.beyondBounds && s.pixels ? &*r.beyondBounds : nullptr;
    rows.push_back(
        {{"passes_asked", r.passesAsked},
         {"passes", r.passes},
         {"ms_per_frame", r.msPerFrame},
         {"mean_abs_shadow", s.pixels ? nlohmann::json(s.meanAbs) : nullptr},
         {"p99_abs_shadow", s.pixels ? nlohmann::json(s.p99Abs) : nullptr},
         {"shadow_pixels", s.pixels},
         {"mean_abs_frame", c.frame.meanAbs},
         {"ssim", c.ssim},
         {"psnr", orNull(c.frame.psnr)},
         {"flip", c.frame.flipMean},
         {"flip_shadow", s.pixels ? nlohmann::json(s.flipMean) : nullptr},
         {"contact_pixels", r.contact.bandPixels},
         {"mean_abs_contact", r.contact.meanAbs},
         {"mean_signed_contact", r.contact.meanSigned},
         {"spurious_shadow_pixels", r.contact.spuriousPixels},
         {"mean_beyond_bounds_shadow", beyond ? nlohmann::json(beyond->meanAbs) : nullptr},
         {"p99_beyond_bounds_shadow", beyond ? nlohmann::json(beyond->p99Abs) : nullptr}});
  }
  return {{"bundle", bundlePath},
          {"reference", report.reference},
          {"shadow_map", o.shadowMapSize},
          {"fine_proxy_passes", o.fineProxyPasses},
          {"product_fine_proxy_passes", o.productFineProxyPasses},
          {"area_penumbrae", o.areaPenumbrae},
          {"texels_per_shadow_pixel", o.texelsPerShadowPixel},
          {"flip_ppd", o.pixelsPerDegree},
          {"width", report.width},
          {"height", report.height},
          {"frames_timed", o.frames},
          {"pose", pose},
          {"results", rows},
          {"accumulation", raster::accumulationName(o.accumulation)},
          {"per_cluster_shares", o.perClusterShares},
          {"depth_bias", o.depthBias},
          {"contact_radius", o.contactRadius}};
}

}  // namespace penumbra::reference
