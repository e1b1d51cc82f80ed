#include "scene/camera_calibration.h"

#include <charconv>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace penumbra::scene {
namespace {

// The board's corners in its own plane (z = 0), row-major, as calibrateCamera wants them.
std::vector<cv::Point3f> boardPoints(ChessboardSize board, double squareSize) {
  std::vector<cv::Point3f> pts;
  for (int r = 0; r < board.rows; ++r) {
    for (int c = 0; c < board.cols; ++c) {
      pts.emplace_back(float(c * squareSize), float(r * squareSize), 0.0f);
    }
  }
  return pts;
}

std::string boardName(ChessboardSize board) {
  return std::to_string(board.cols) + "x" + std::to_string(board.rows);
}

void checkBoard(ChessboardSize board) {
  if (board.cols < 2 || board.rows < 2) {
    throw CalibrationError("chessboard " + boardName(board) + ": needs at least 2x2 inner corners");
  }
}

// Runs calibrateCamera on the views in `found` and fills `out` (intrinsics, rms, poses,
// per-view rms of the used images in `out.images`).
void calibrate(const std::vector<std::vector<cv::Point2f>>& found, ChessboardSize board,
               cv::Size size, double squareSize, ChessboardCalibration& out) {
  const std::vector<std::vector<cv::Point3f>> objects(found.size(), boardPoints(board, squareSize));
  cv::Mat camera = cv::Mat::eye(3, 3, CV_64F), dist = cv::Mat::zeros(5, 1, CV_64F);
  std::vector<cv::Mat> rvecs, tvecs;
  cv::Mat stdIn, stdEx, perView;
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12);
  out.rmsPx = cv::calibrateCamera(objects, found, size, camera, dist, rvecs, tvecs, stdIn, stdEx,
                                  perView, 0, criteria);
  Intrinsics& k = out.intrinsics;
  k.width = size.width;
  k.height = size.height;
  k.fx = camera.at<double>(0, 0);
  k.fy = camera.at<double>(1, 1);
  k.cx = camera.at<double>(0, 2);
  k.cy = camera.at<double>(1, 2);
  k.k1 = dist.at<double>(0);
  k.k2 = dist.at<double>(1);
  k.p1 = dist.at<double>(2);
  k.p2 = dist.at<double>(3);
  k.k3 = dist.at<double>(4);
  if (!std::isfinite(out.rmsPx) || !(k.fx > 0) || !(k.fy > 0)) {
    throw CalibrationError("chessboard calibration did not converge (rms " +
                           std::to_string(out.rmsPx) + ")");
  }
  size_t view = 0;
  for (ChessboardImage& im : out.images) {
    if (!im.used) continue;
    cv::Mat r;
    cv::Rodrigues(rvecs[view], r);
    Pose pose;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) pose.rotation[j][i] = r.at<double>(i, j);  // glm: [col][row]
      pose.translation[i] = tvecs[view].at<double>(i);
    }
    out.poses.push_back(pose);
    im.rmsPx = perView.at<double>(int(view));
    ++view;
  }
}

std::string skippedList(const ChessboardCalibration& c) {
  std::string s;
  for (const ChessboardImage& im : c.images) {
    if (!im.used) s += "\n  " + im.problem;
  }
  return s;
}

}  // namespace

int ChessboardCalibration::usedCount() const {
  int n = 0;
  for (const ChessboardImage& im : images) n += im.used ? 1 : 0;
  return n;
}

ChessboardSize parseChessboardSize(const std::string& text) {
  // from_chars, not sscanf: "%d" of a number past INT_MAX is undefined behaviour.
  ChessboardSize b;
  const char* const end = text.data() + text.size();
  const auto cols = std::from_chars(text.data(), end, b.cols);
  const bool separator =
      cols.ec == std::errc() && cols.ptr != end && (*cols.ptr == 'x' || *cols.ptr == 'X');
  const auto rows = separator ? std::from_chars(cols.ptr + 1, end, b.rows)
                              : std::from_chars_result{end, std::errc::invalid_argument};
  if (!separator || rows.ec != std::errc() || rows.ptr != end) {
    throw CalibrationError("chessboard size '" + text +
                           "': expected COLSxROWS inner corners, e.g. 9x6");
  }
  checkBoard(b);
  return b;
}

ChessboardViews findChessboards(const std::vector<std::filesystem::path>& photos,
                                ChessboardSize board, const CornerSearch& search) {
  checkBoard(board);
  if (search.refineHalfWindow < 1) {
    throw CalibrationError("corner refinement window must be at least 1");
  }
  const bool classic = search.detector == CornerSearch::Detector::kClassic;
  ChessboardViews out;
  cv::Size size;
  for (const std::filesystem::path& path : photos) {
    ChessboardImage im;
    im.file = path.string();
    const std::string name = path.filename().string();
    // Check existence first: imread on a missing file also logs an OpenCV warning.
    std::error_code ec;
    const cv::Mat grey = std::filesystem::is_regular_file(path, ec)
                             ? cv::imread(path.string(), cv::IMREAD_GRAYSCALE)
                             : cv::Mat();
    if (grey.empty()) {
      im.problem =
          name + (std::filesystem::exists(path, ec) ? ": cannot read the image" : ": no such file");
    } else if (!out.corners.empty() && grey.size() != size) {
      im.problem = name + ": size " + std::to_string(grey.cols) + "x" + std::to_string(grey.rows) +
                   " differs from the first photo's " + std::to_string(size.width) + "x" +
                   std::to_string(size.height);
    } else {
      std::vector<cv::Point2f> corners;
      const cv::Size pattern(board.cols, board.rows);
      const bool ok = classic ? cv::findChessboardCorners(
                                    grey, pattern, corners,
                                    cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE)
                              : cv::findChessboardCornersSB(grey, pattern, corners,
                                                            cv::CALIB_CB_NORMALIZE_IMAGE |
                                                                cv::CALIB_CB_EXHAUSTIVE |
                                                                cv::CALIB_CB_ACCURACY);
      if (!ok) {
        im.problem = name + ": no " + boardName(board) + " chessboard found";
      } else {
        // Refine to sub-pixel accuracy: the classic detector is pixel-accurate only.
        if (classic) {
          cv::cornerSubPix(
              grey, corners, cv::Size(search.refineHalfWindow, search.refineHalfWindow),
              cv::Size(-1, -1),
              cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.001));
        }
        if (out.corners.empty()) size = grey.size();
        std::vector<glm::dvec2> view;
        view.reserve(corners.size());
        for (const cv::Point2f& p : corners) view.emplace_back(p.x, p.y);  // exact: float -> double
        out.corners.push_back(std::move(view));
        im.used = true;
      }
    }
    out.images.push_back(std::move(im));
  }
  out.width = size.width;
  out.height = size.height;
  return out;
}

ChessboardCalibration calibrateFromChessboards(const std::vector<std::filesystem::path>& photos,
                                               ChessboardSize board, double squareSize,
                                               int minImages) {
  checkBoard(board);
  if (minImages < 3) minImages = 3;  // Zhang's method needs three views of a plane
  if (!(squareSize > 0) || !std::isfinite(squareSize)) {
    throw CalibrationError("chessboard square size must be positive");
  }
  ChessboardViews views = findChessboards(photos, board);
  ChessboardCalibration out;
  out.images = std::move(views.images);
  if (int(views.corners.size()) < minImages) {
    throw CalibrationError("chessboard calibration: " + std::to_string(views.corners.size()) +
                           " of " + std::to_string(photos.size()) +
                           " photos usable, need at least " + std::to_string(minImages) +
                           skippedList(out));
  }
  std::vector<std::vector<cv::Point2f>> found;
  found.reserve(views.corners.size());
  for (const std::vector<glm::dvec2>& view : views.corners) {
    std::vector<cv::Point2f> pts;
    pts.reserve(view.size());
    for (const glm::dvec2& p : view) pts.emplace_back(float(p.x), float(p.y));  // the same floats
    found.push_back(std::move(pts));
  }
  calibrate(found, board, cv::Size(views.width, views.height), squareSize, out);
  return out;
}

ChessboardCalibration calibrateFromCorners(const std::vector<std::vector<glm::dvec2>>& corners,
                                           ChessboardSize board, int width, int height,
                                           double squareSize,
                                           const std::vector<std::string>& names) {
  checkBoard(board);
  if (width <= 0 || height <= 0) throw CalibrationError("image size must be positive");
  if (corners.size() < 3) {
    throw CalibrationError("chessboard calibration: " + std::to_string(corners.size()) +
                           " views, need at least 3");
  }
  ChessboardCalibration out;
  std::vector<std::vector<cv::Point2f>> found;
  for (size_t v = 0; v < corners.size(); ++v) {
    const std::string name = v < names.size() ? names[v] : "view " + std::to_string(v);
    if (corners[v].size() != size_t(board.cols) * size_t(board.rows)) {
      throw CalibrationError(name + ": " + std::to_string(corners[v].size()) + " corners, a " +
                             boardName(board) + " board has " +
                             std::to_string(board.cols * board.rows));
    }
    std::vector<cv::Point2f> pts;
    for (const glm::dvec2& p : corners[v]) {
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
        throw CalibrationError(name + ": corner is not a finite number");
      }
      pts.emplace_back(float(p.x), float(p.y));
    }
    found.push_back(std::move(pts));
    ChessboardImage im;
    im.file = name;
    im.used = true;
    out.images.push_back(im);
  }
  calibrate(found, board, cv::Size(width, height), squareSize, out);
  return out;
}

}  // namespace penumbra::scene
