// `penumbra compare A.png B.png [--mask M.png] [--json out.json] [--heatmap out.png] [--ppd P]`:
// the image metrics of reference/image_metrics.h between a reference A and a test image B
// (mean / p99 / max absolute 8-bit error, PSNR, SSIM, LDR-FLIP), as one JSON object on
// stdout (or in --json, with a one-line summary on stdout), and the FLIP map as a heat-map
// PNG. Present when built with PENUMBRA_WITH_OPENCV; otherwise adds nothing.
#pragma once

#include <vector>

#include "apps/scene_commands.h"

namespace penumbra::apps {

std::vector<Command> addCompareCommands(CLI::App& app);

}  // namespace penumbra::apps
