// Camera pose from marked room corners (issue 4 item 2; Gibson & Chalmers 2003 §3 fit the
// room model to the photograph): given calibrated intrinsics and N >= 4 image marks of
// known 3D points of the room (in the room JSON's frame), OpenCV's solvePnP (iterative,
// from an EPnP start) followed by Levenberg–Marquardt refinement gives the pose; the
// reprojection error says how well the room model and the marks agree.
//
// Part of penumbra_calibration (PENUMBRA_WITH_OPENCV); no OpenCV type in this header.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/camera_intrinsics.h"

namespace penumbra::scene {

struct CornerMark {
  std::string name;       // e.g. "floor back left", for messages
  glm::dvec3 world{0.0};  // room coordinates (metres)
  glm::dvec2 image{0.0};  // pixels, calibration convention (camera_intrinsics.h)
};

struct PoseFit {
  Pose pose;                        // world -> camera
  std::vector<double> residualsPx;  // per mark, same order
  double rmsPx = 0, maxPx = 0;
};

// Throws CalibrationError (prefixed with `source`, e.g. the marks file name) for fewer than
// four marks, non-finite values, marks whose world points are (nearly) collinear or
// coincident, or a fit that puts a mark behind the camera.
PoseFit fitPose(const Intrinsics& intrinsics, const std::vector<CornerMark>& marks,
                const std::string& source = "corner marks");

// Reads {"corners": [{"name": "...", "world": [x, y, z], "image": [u, v]}, ...]}
// (docs/calibration.md). Throws CalibrationError naming the file and the field.
std::vector<CornerMark> loadCornerMarks(const std::filesystem::path& path);

}  // namespace penumbra::scene
