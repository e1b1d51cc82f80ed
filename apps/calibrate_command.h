// `penumbra calibrate` (issue 4 item 9), built when OpenCV is (PENUMBRA_WITH_OPENCV):
//   calibrate --chessboard COLSxROWS [--square S] IMAGE...   intrinsics from chessboard photos
//   calibrate --vanishing MARKS.json                         intrinsics and pose from
//                                                            vanishing points (docs/calibration.md)
//   [--corners CORNERS.json]  also fit the pose to marked room corners (solvePnP)
//   [--json OUT.json]         write the result as JSON (no file on error)
// Prints `key value` lines, among them `reprojection_error_px <value>`.
#pragma once

#include <CLI/CLI.hpp>
#include <vector>

#include "apps/scene_commands.h"

namespace penumbra::apps {

// The calibrate subcommand; empty when built without OpenCV.
std::vector<Command> addCalibrateCommands(CLI::App& app);

}  // namespace penumbra::apps
