// Camera intrinsics from photographs of a chessboard (the desktop route of Gibson &
// Chalmers 2003 §3, where the tutorial marks vanishing points instead): OpenCV's
// findChessboardCorners + cornerSubPix per photo, then calibrateCamera (Zhang's method
// with Levenberg–Marquardt refinement) for fx, fy, cx, cy, k1, k2, p1, p2, k3.
//
// Part of penumbra_calibration (built with PENUMBRA_WITH_OPENCV); this header exposes no
// OpenCV type, so callers need not see OpenCV. Offline only.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/camera_intrinsics.h"

namespace penumbra::scene {

// Inner corners of the chessboard: 9x6 for OpenCV's sample photos (a board of 10x7
// squares).
struct ChessboardSize {
  int cols = 9, rows = 6;
};

// Parses "COLSxROWS", e.g. "9x6"; each at least 2. Throws CalibrationError.
ChessboardSize parseChessboardSize(const std::string& text);

// What happened to one photo.
struct ChessboardImage {
  std::string file;     // as given
  bool used = false;    // corners found and used in the calibration
  std::string problem;  // why not, e.g. "left10.jpg: no 9x6 chessboard found"
  double rmsPx = 0;     // this photo's RMS reprojection error (used photos only)
};

struct ChessboardCalibration {
  Intrinsics intrinsics;
  double rmsPx = 0;  // RMS reprojection error over every corner of every used photo
  std::vector<ChessboardImage> images;
  std::vector<Pose> poses;  // board -> camera, one per used photo, in input order
  int usedCount() const;
};

// How corners are searched for. kClassic: OpenCV's findChessboardCorners (adaptive
// threshold, normalised image: quads found by contour), then cornerSubPix with a search window
// of (2 * refineHalfWindow + 1) pixels square — the room camera's calibration, whose results
// stay as they were (11: a 23-pixel window, OpenCV's sample value, for photos whose squares
// are ~40 pixels). kSectorBased: findChessboardCornersSB (Duda & Frese 2018, OpenCV's
// recommended detector; sub-pixel by itself, no cornerSubPix) with CALIB_CB_EXHAUSTIVE and
// CALIB_CB_ACCURACY — the fisheye calibration's: on boards squeezed to 6-12-pixel squares by a
// fisheye lens the classic detector found 4 of 13 views in the tests, this one 13 of 13.
struct CornerSearch {
  enum class Detector { kClassic, kSectorBased };
  Detector detector = Detector::kClassic;
  int refineHalfWindow = 11;  // kClassic only
};

// The chessboard corners of each photo, as both calibrations find them (the pinhole one
// here, the environment camera's fisheye one in envmap/fisheye_calibration.h).
struct ChessboardViews {
  int width = 0, height = 0;                     // of the first usable photo
  std::vector<ChessboardImage> images;           // one per photo, in input order
  std::vector<std::vector<glm::dvec2>> corners;  // per used photo, row-major over the board
};
// Photos that cannot be read, have another size than the first usable one, or show no
// complete board are not used, and named in `images[i].problem`. Throws CalibrationError for
// a board of fewer than 2x2 inner corners; never for a photo.
ChessboardViews findChessboards(const std::vector<std::filesystem::path>& photos,
                                ChessboardSize board, const CornerSearch& search = {});

// Calibrates from photos. Photos that cannot be read, have another size than the first
// readable one, or show no complete board are skipped and named in `images[i].problem`.
// Throws CalibrationError, naming every skipped photo and why, when fewer than
// `minImages` (>= 3) are usable. `squareSize` sets the unit of the poses' translations.
ChessboardCalibration calibrateFromChessboards(const std::vector<std::filesystem::path>& photos,
                                               ChessboardSize board, double squareSize = 1.0,
                                               int minImages = 3);

// The same from corners already found (row-major over the board, cols per row), e.g. a
// synthetic board projected through a known camera. `names` labels the views in errors
// and reports (may be empty). Throws CalibrationError on too few views, wrong corner
// counts or non-finite corners.
ChessboardCalibration calibrateFromCorners(const std::vector<std::vector<glm::dvec2>>& corners,
                                           ChessboardSize board, int width, int height,
                                           double squareSize = 1.0,
                                           const std::vector<std::string>& names = {});

}  // namespace penumbra::scene
