// `penumbra capture MANIFEST.json -o BUNDLE [--threads N]` (issue 4 item 8): photographs,
// calibration marks, the room JSON and a light probe -> a scene bundle (lighting/capture.h,
// docs/capture.md). A progress bar with the stage names on stderr, a summary on stdout;
// no bundle is written on error. Empty when built without penumbra_capture (Embree, OpenCV,
// OpenEXR).
#pragma once

#include <CLI/CLI.hpp>
#include <vector>

#include "apps/scene_commands.h"

namespace penumbra::apps {

std::vector<Command> addCaptureCommands(CLI::App& app);

}  // namespace penumbra::apps
