// `penumbra calibrate` (issue 4 item 9), built when OpenCV is (PENUMBRA_WITH_OPENCV):
//   calibrate --chessboard COLSxROWS [--square S] IMAGE...   intrinsics from chessboard photos
//   calibrate --vanishing MARKS.json                         intrinsics and pose from
//                                                            vanishing points (docs/calibration.md)
//   [--corners CORNERS.json]  also fit the pose to marked room corners (solvePnP)
//   [--json OUT.json]         write the result as JSON (no file on error)
// Prints `key value` lines, among them `reprojection_error_px <value>`.
//
// `penumbra calibrate-fisheye PHOTO... --board COLSxROWS --square M -o LENS.json` (issue 16
// item 1), built with OpenCV's fisheye module (penumbra_envmap_fisheye): the environment
// camera's lens (envmap/fisheye_calibration.h) as a lens file (envmap/fisheye_lens_file.h).
// Prints `key value` lines (fx ... k4, `reprojection_error_px`, `reach_deg`); a fit over 5 px
// RMS, a missing photo, a bad --board or too few photos with the whole board are errors
// (exit 1, 2 for --board) and write no file; a lens that does not reach 90° is written with a
// warning (the kiosk refuses it).
#pragma once

#include <CLI/CLI.hpp>
#include <vector>

#include "apps/scene_commands.h"

namespace penumbra::apps {

// The calibrate subcommand; empty when built without OpenCV.
std::vector<Command> addCalibrateCommands(CLI::App& app);

}  // namespace penumbra::apps
