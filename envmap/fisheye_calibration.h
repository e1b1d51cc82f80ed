// The environment camera's lens from chessboard photos (issue 16 item 1): the corners found by
// the same code as the room camera's calibration (scene::findChessboards, with OpenCV's
// sector-based detector: a fisheye squeezes the board's squares to a few pixels), then OpenCV's
// fisheye calibration (cv::fisheye::calibrate: the equidistant model with θ_d = θ (1 + k1 θ² +
// k2 θ⁴ + k3 θ⁶ + k4 θ⁸), Kannala & Brandt 2006, as OpenCV documents it), giving the lens file
// of fisheye_lens_file.h that the kiosk's hemisphere map (Havran et al. 2005 §5.1) is resampled
// with. `penumbra calibrate-fisheye` is this function and a write.
//
// Part of penumbra_envmap_fisheye (OpenCV); offline only. Cost: the corner search per photo
// (~0.1 s at 480 × 480) and one Levenberg–Marquardt fit.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "envmap/fisheye_lens_file.h"
#include "scene/camera_calibration.h"

namespace penumbra::envmap {

struct FisheyeCalibration {
  FisheyeLensFile lens;                        // what the lens file holds
  std::vector<scene::ChessboardImage> images;  // per photo: used, or why not; per-view RMS
  double reach = 0;                            // nearestEdgeReach(lens.lens), radians
};

// Calibrates from `photos` of a board of `board` inner corners and squares of `square` (any
// unit; it sets only the poses' scale, which the lens file does not keep). Throws FisheyeError
// (messages naming the photos) when fewer than `minViews` (≥ 3) photos show the whole board,
// when OpenCV's fit fails or does not converge, and when its RMS reprojection error is over
// kMostFisheyeRmsPx ("… px, more than 5 px: …"); CalibrationError for a board of fewer than
// 2x2 corners or a square that is not positive.
FisheyeCalibration calibrateFisheye(const std::vector<std::filesystem::path>& photos,
                                    scene::ChessboardSize board, double square, int minViews = 3);

// The fit alone, from corners already found (scene::findChessboards; `views.images` names the
// photos, `views.corners` holds one entry per used photo, in order): what calibrateFisheye
// does after its corner search, with the same refusals.
FisheyeCalibration fitFisheyeLens(scene::ChessboardViews views, scene::ChessboardSize board,
                                  double square, int minViews = 3);

}  // namespace penumbra::envmap
