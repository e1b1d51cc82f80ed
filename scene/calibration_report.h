// `penumbra calibrate` as a library function (design §1 step 1, tutorial §3): the kiosk
// camera's intrinsics from chessboard photographs (scene/camera_calibration.h) or from two
// marked vanishing points and a marked origin (scene/vanishing_points.h, which also gives the
// pose), optionally the pose refitted to marked room corners (scene/room_pose.h), and the
// JSON document the command writes (docs/calibration.md). Needs OpenCV
// (penumbra_calibration). Cost: the chosen calibration's.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/camera_calibration.h"
#include "scene/camera_intrinsics.h"
#include "scene/room_pose.h"
#include "scene/vanishing_points.h"

namespace penumbra::scene {

// Exactly one of `chessboard` (inner corners "COLSxROWS", with `images`) and `vanishing`
// (a marks file); `corners` (a corner-marks file) is optional.
struct CalibrationRequest {
  std::string chessboard;
  double square = 1.0;  // chessboard square size, the unit of the poses
  std::vector<std::string> images;
  std::string vanishing;
  std::string corners;
};

struct CalibrationReport {
  Intrinsics intrinsics;
  std::optional<ChessboardCalibration> chessboard;  // set by the chessboard method
  std::optional<VanishingCalibration> vanishing;    // set by the vanishing-point method
  std::optional<PoseFit> corners;                   // set when corners were given
  // {"method", "board" or "marks", "intrinsics", ["pose"], "reprojection_error_px",
  //  ["images"], ["corners_pose", "corners_reprojection_error_px"]}.
  nlohmann::json json;
};

// Throws std::invalid_argument for a request naming no method or both, or chessboards
// without images; CalibrationError (and file errors) from the calibrations themselves.
CalibrationReport calibrateCamera(const CalibrationRequest& request);

// {"width", "height", "fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3"}.
nlohmann::json toJson(const Intrinsics& k);
// {"rotation_world_to_camera" (row-major 3x3), "translation", "camera_position"}.
nlohmann::json toJson(const Pose& p);

// Writes `doc` (indented by 2, a final newline) with core::writeFileReplacing: an interrupted
// or failed run leaves no half-written result; errors are core::Error naming `path`.
void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& doc);

}  // namespace penumbra::scene
