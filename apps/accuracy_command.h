// `penumbra accuracy BUNDLE --passes 10,20,50 [--json out.json] [--reference REF.png]
// [--mask M.png]`: per pass count, ms/frame and the error of the showroom frame at the
// bundle's start pose against a reference image (design §4, issue 5): passes, ms_per_frame,
// mean_abs_shadow, p99_abs_shadow, ssim, psnr, flip (reference/image_metrics.h).
// The reference: by default the ray-traced ground truth (reference/reference_renderer.h,
// --spp/--light-samples/--bounces/--seed), rendered at the same pose, and its shadow mask
// as the region; --reference REF.png to use an image instead; --penumbra-reference (and
// always when built without Embree) a high-quality Penumbra render (2048² shadow map, every
// occluded source its own pass). The JSON's "reference" says which. Without the ray
// tracer's mask the region is --mask, or the pixels where the reference differs from the
// zero-pass frame (background + product). Present with PENUMBRA_WITH_OPENCV.
#pragma once

#include <vector>

#include "apps/scene_commands.h"

namespace penumbra::apps {

std::vector<Command> addAccuracyCommands(CLI::App& app);

}  // namespace penumbra::apps
