// `penumbra camera-response IMAGE:EXPOSURE_US IMAGE:EXPOSURE_US ... -o RESPONSE.json
// [--samples 400] [--smoothness 10]` (issue 16 item 1): the environment camera's response
// recovered from an 8-bit bracket — the same still scene photographed at two or more exposure
// times, fixed gain and white balance — by Debevec & Malik 1997's solve
// (lighting::recoverResponse: deterministic, the same curve from the same bracket), written as
// the file kiosk.json's "environment": {"response": "RESPONSE.json"} names
// (kiosk/camera_response_file.h). Prints per channel the range of g and the codes the
// monotone repair changed, and the solver's warnings. Present when built with OpenCV (the
// photographs are read by scene::readPhotoRgb8); otherwise it adds nothing.
#pragma once

#include <CLI/CLI.hpp>
#include <vector>

#include "apps/scene_commands.h"

namespace penumbra::apps {

std::vector<Command> addCameraResponseCommands(CLI::App& app);

}  // namespace penumbra::apps
