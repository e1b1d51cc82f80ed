#include "envmap/fisheye_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

namespace penumbra::envmap {

namespace {

std::string skipped(const std::vector<scene::ChessboardImage>& images) {
  std::string s;
  for (const scene::ChessboardImage& im : images) {
    if (!im.used) s += "\n  " + im.problem;
  }
  return s;
}

std::string fixed(double v, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}

}  // namespace

FisheyeCalibration calibrateFisheye(const std::vector<std::filesystem::path>& photos,
                                    scene::ChessboardSize board, double square, int minViews) {
  if (!(square > 0) || !std::isfinite(square)) {
    throw scene::CalibrationError("chessboard square size must be positive");
  }
  return fitFisheyeLens(
      scene::findChessboards(photos, board, {scene::CornerSearch::Detector::kSectorBased}), board,
      square, minViews);
}

FisheyeCalibration fitFisheyeLens(scene::ChessboardViews views, scene::ChessboardSize board,
                                  double square, int minViews) {
  if (!(square > 0) || !std::isfinite(square)) {
    throw scene::CalibrationError("chessboard square size must be positive");
  }
  // Zhang's initialisation, which cv::fisheye::calibrate's extrinsics start from, needs three
  // views of a plane.
  minViews = std::max(minViews, 3);
  FisheyeCalibration out;
  out.images = std::move(views.images);
  const int found = int(views.corners.size());
  // The per-photo bookkeeping below walks the used photos and the views together.
  const auto used = std::count_if(out.images.begin(), out.images.end(),
                                  [](const scene::ChessboardImage& im) { return im.used; });
  if (used != found) {
    throw scene::CalibrationError("fisheye calibration: " + std::to_string(used) +
                                  " photos marked used for " + std::to_string(found) + " views");
  }
  for (const std::vector<glm::dvec2>& view : views.corners) {
    if (view.size() != size_t(board.cols) * size_t(board.rows)) {
      throw scene::CalibrationError(
          "fisheye calibration: a view of " + std::to_string(view.size()) + " corners for a " +
          std::to_string(board.cols) + "x" + std::to_string(board.rows) + " board");
    }
  }
  if (found < minViews) {
    throw FisheyeError("fisheye calibration", "",
                       std::to_string(found) + " of " + std::to_string(out.images.size()) +
                           " photos show the whole " + std::to_string(board.cols) + "x" +
                           std::to_string(board.rows) + " board, need at least " +
                           std::to_string(minViews) + skipped(out.images));
  }
  // cv::fisheye wants the board's points as 1 × N CV_64FC3 and the corners as 1 × N CV_64FC2.
  std::vector<cv::Point3d> boardPoints;
  for (int r = 0; r < board.rows; ++r)
    for (int c = 0; c < board.cols; ++c) boardPoints.emplace_back(c * square, r * square, 0.0);
  std::vector<cv::Mat> objects, corners;
  for (const std::vector<glm::dvec2>& view : views.corners) {
    objects.push_back(cv::Mat(boardPoints, true).reshape(3, 1));
    std::vector<cv::Point2d> pts;
    pts.reserve(view.size());
    for (const glm::dvec2& p : view) pts.emplace_back(p.x, p.y);
    corners.push_back(cv::Mat(pts, true).reshape(2, 1));
  }
  const cv::Size size(views.width, views.height);
  cv::Matx33d camera;
  cv::Vec4d distortion;
  std::vector<cv::Vec3d> rvecs, tvecs;
  // OpenCV's recommended flags (its fisheye calibration documentation): extrinsics re-estimated
  // at every iteration, no skew. Without CALIB_CHECK_COND: a view whose Jacobian is
  // ill-conditioned would end the whole fit with an exception naming an array index; the RMS
  // check below refuses a fit that such a view spoils.
  const int flags = cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC | cv::fisheye::CALIB_FIX_SKEW;
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12);
  double rms = 0;
  try {
    rms = cv::fisheye::calibrate(objects, corners, size, camera, distortion, rvecs, tvecs, flags,
                                 criteria);
  } catch (const cv::Exception& e) {
    throw FisheyeError("fisheye calibration", "",
                       "OpenCV's fit failed (" + e.err + ") over " + std::to_string(found) +
                           " views: photos of the board from more directions, filling more of "
                           "the image, may help");
  }
  FisheyeLens& lens = out.lens.lens;
  lens.width = uint32_t(size.width);
  lens.height = uint32_t(size.height);
  lens.fx = camera(0, 0);
  lens.fy = camera(1, 1);
  // OpenCV's image coordinates have pixel centres at integers (as the corner finder reports
  // them); FisheyeLens's have the image's corner at 0: half a pixel further.
  lens.cx = camera(0, 2) + 0.5;
  lens.cy = camera(1, 2) + 0.5;
  for (int i = 0; i < 4; ++i) lens.k[size_t(i)] = distortion[i];
  const bool finite = std::isfinite(rms) && std::isfinite(lens.fx) && std::isfinite(lens.fy) &&
                      std::isfinite(lens.cx) && std::isfinite(lens.cy) &&
                      std::isfinite(lens.k[0]) && std::isfinite(lens.k[1]) &&
                      std::isfinite(lens.k[2]) && std::isfinite(lens.k[3]);
  if (!finite || !(lens.fx > 0) || !(lens.fy > 0)) {
    throw FisheyeError("fisheye calibration", "",
                       "OpenCV's fit did not converge (rms " + fixed(rms, 4) + " px, fx " +
                           fixed(lens.fx, 3) + ", fy " + fixed(lens.fy, 3) + ")");
  }
  // Each used photo's own RMS, from its pose.
  size_t view = 0;
  for (scene::ChessboardImage& im : out.images) {
    if (!im.used) continue;
    std::vector<cv::Point2d> projected;
    cv::fisheye::projectPoints(boardPoints, projected, rvecs[view], tvecs[view], camera,
                               distortion);
    double sum = 0;
    for (size_t i = 0; i < projected.size(); ++i) {
      const glm::dvec2 d = glm::dvec2(projected[i].x, projected[i].y) - views.corners[view][i];
      sum += d.x * d.x + d.y * d.y;
    }
    im.rmsPx = std::sqrt(sum / double(projected.size()));
    ++view;
  }
  if (!(rms <= kMostFisheyeRmsPx)) {
    std::string worst;
    double worstRms = -1;
    for (const scene::ChessboardImage& im : out.images) {
      if (im.used && im.rmsPx > worstRms) {
        worstRms = im.rmsPx;
        worst = std::filesystem::path(im.file).filename().string();
      }
    }
    throw FisheyeError("fisheye calibration", "",
                       "RMS reprojection error " + fixed(rms, 3) + " px, more than " +
                           fixed(kMostFisheyeRmsPx, 0) + " px: not a calibration of this lens (" +
                           "is the board size right? the worst photo is " + worst + ", " +
                           fixed(worstRms, 3) + " px)");
  }
  out.lens.rmsPx = rms;
  out.lens.views = found;
  out.lens.board = std::to_string(board.cols) + "x" + std::to_string(board.rows);
  out.lens.square = square;
  // A fit that passes its own RMS must still be a lens the file can hold (centre inside).
  if (!(lens.cx > 0 && lens.cx < lens.width && lens.cy > 0 && lens.cy < lens.height)) {
    throw FisheyeError("fisheye calibration", "",
                       "the fitted centre (" + fixed(lens.cx, 2) + ", " + fixed(lens.cy, 2) +
                           ") is outside the image");
  }
  out.reach = nearestEdgeReach(lens);
  return out;
}

}  // namespace penumbra::envmap
