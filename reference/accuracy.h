// `penumbra accuracy` as a library function (design §4, issue 5): per pass count, the
// median ms/frame of the per-frame loop (shadow::FrameLoop) with the product sliding a
// little, and the error of the still frame at one pose (the bundle's start pose unless
// AccuracyOptions::pose says otherwise; issue 15) against a reference
// image — in its shadow region (reference/shadow_region.h), in the contact band and over
// the whole frame (reference/image_metrics.h).
//
// The reference: an image file (referencePath), the ray-traced ground truth
// (reference/reference_renderer.h; only when penumbra_accuracy was built with the ray
// tracer, see accuracyHasRayTracer()) whose shadow mask becomes the region, or the
// Penumbra stand-in (penumbraReference: a large shadow map, every occluded source its own
// pass). Without the ray tracer's mask the region is maskPath, or the pixels where the
// reference differs from the zero-pass frame (background + product).
//
// Cost: the reference (the ray tracer dominates when used) plus, per pass count,
// frames + 3 frames of the loop and one image comparison (SSIM and FLIP over the frame).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "raster/frame_trace.h"
#include "raster/renderer.h"
#include "reference/flip.h"
#include "reference/image_metrics.h"
#include "reference/reference_renderer.h"
#include "reference/shadow_region.h"
#include "shadow/frame_compositor.h"
#include "shadow/scene_bundle.h"

namespace penumbra::reference {

struct AccuracyOptions {
  std::vector<int> passes{10, 20, 50};  // pass counts measured, in this order
  int frames = 5;                       // timed frames per pass count (median)
  uint32_t shadowMapSize = 256;
  double pixelsPerDegree = FlipOptions{}.pixelsPerDegree;  // FLIP viewing condition
  raster::RenderOptions render;
  // The pipeline measured (shadow::CompositorOptions): how the passes are summed, one
  // occluded share per cluster (or per vertex), the receivers' depth bias, and the radius
  // of the contact band in pixels, and how many passes draw the fine proxy.
  raster::Accumulation accumulation = raster::Accumulation::kLinear;
  bool perClusterShares = true;
  float depthBias = shadow::CompositorOptions{}.depthBias;
  uint32_t fineProxyPasses = shadow::CompositorOptions{}.fineProxyPasses;
  std::vector<uint32_t> productFineProxyPasses;  // empty, or per product in its place
  bool areaPenumbrae = shadow::CompositorOptions{}.areaPenumbrae;
  double texelsPerShadowPixel = 0;   // a map per cluster (shadow/cluster_map_size.h); 0: off
  shadow::ShaftBuildOptions shafts;  // pruning fraction and receivers per leaf (§6)
  int contactRadius = 8;

  std::string referencePath;       // a reference PNG of the view's size; empty: rendered
  std::string maskPath;            // a shadow-region PNG; empty: from the reference
  bool penumbraReference = false;  // the stand-in instead of rays (always without them)
  uint32_t referenceMapSize = 2048;
  size_t referencePasses = 1000;
  ReferenceOptions rays;  // the ray-traced reference's sampling

  std::string referenceOut, maskOut;  // when set, the reference and region used as PNG
  // The reference's bounds (reference/differential.h: where the photograph's 8 bits leave it
  // open), lower and upper PNG: read with referencePath (both or neither), written when set
  // and the reference is ray-traced here.
  std::string referenceLowerPath, referenceUpperPath;
  std::string referenceLowerOut, referenceUpperOut;
  // When set, each measured frame as PNG: framesOut with "-<passes asked>" before ".png".
  std::string framesOut;
  // The product and pose measured (`--product`, `--pose`); unset: the bundle's start pose.
  std::optional<shadow::ProductPose> pose;
};

// The pose `o` measures: o.pose or the bundle's start pose. Throws std::invalid_argument
// for a product the bundle does not have.
shadow::ProductPose measuredPose(const shadow::SceneBundle& bundle, const AccuracyOptions& o);

// One pass count's result (the still frame at the start pose against the reference).
struct AccuracyRow {
  int passesAsked = 0;
  uint32_t passes = 0;  // the passes the frame drew (fewer when fewer sources are occluded)
  double msPerFrame = 0;
  ImageComparison comparison;  // comparison.masked: the shadow region
  ContactErrors contact;
  // In the shadow region, how far the frame lies outside the reference's bounds (image_
  // metrics.h, intervalErrors); absent when the reference has none (an image without its
  // bounds, the Penumbra stand-in).
  std::optional<RegionErrors> beyondBounds;
};

struct AccuracyReport {
  nlohmann::json reference;  // which reference: kind and its settings ("kind": image, ...)
  uint32_t width = 0, height = 0;
  std::vector<AccuracyRow> rows;
};

// True when this build can ray-trace the reference (Embree).
bool accuracyHasRayTracer();

// What a frame at one pose is measured against: the reference image, its shadow region
// (the ray tracer's mask, maskPath's, or the region rule's; without the product's pixels)
// and the shadow-free frame (background + product: the contact band's base).
struct PoseReference {
  core::Image8 image, region;
  core::Image8 lower, upper;        // the reference's bounds; empty when it has none
  std::vector<uint8_t> unshadowed;  // RGBA8
  core::Image8 productRegion;       // the product's own pixels (productPixels of unshadowed)
  nlohmann::json info;              // which reference: kind and its settings
};

// The reference at `pose` as measureAccuracy makes it from `options` (its reference fields,
// rays and render options; the pose fields are not read). Throws MetricsError for a
// reference or mask of the wrong size.
PoseReference makePoseReference(const shadow::SceneBundle& bundle, const AccuracyOptions& options,
                                const shadow::ProductPose& pose);

// Throws MetricsError for a reference or mask of the wrong size and what loading the images
// throws. `onRow` (when set) sees each row as soon as it is measured.
AccuracyReport measureAccuracy(const shadow::SceneBundle& bundle, const AccuracyOptions& options,
                               const std::function<void(const AccuracyRow&)>& onRow = {});

// The JSON `penumbra accuracy` writes: the settings of `options`, the reference and one
// object per row (passes_asked, passes, ms_per_frame, mean_abs_shadow, p99_abs_shadow,
// shadow_pixels, mean_abs_frame, ssim, psnr, flip, flip_shadow, contact_pixels,
// mean_abs_contact, mean_signed_contact, spurious_shadow_pixels, mean_beyond_bounds_shadow,
// p99_beyond_bounds_shadow); null where a value is not finite, the shadow region is empty or
// the reference has no bounds.
nlohmann::json toJson(const std::string& bundlePath, const AccuracyOptions& options,
                      const AccuracyReport& report);

}  // namespace penumbra::reference
