#include "scene/camera_calibration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "scene/calibration_test_util.h"

namespace penumbra::scene {
namespace {

using testutil::lookFrom;

// A known 640x480 camera with lens distortion; a 9x6 board (25 mm squares) seen from ten
// positions, corners projected through the full model.
Intrinsics knownCamera() {
  Intrinsics k;
  k.width = 640;
  k.height = 480;
  k.fx = 532.8;
  k.fy = 531.3;
  k.cx = 322.1;
  k.cy = 236.4;
  k.k1 = -0.21;
  k.k2 = 0.09;
  k.p1 = 0.0012;
  k.p2 = -0.0008;
  k.k3 = -0.02;
  return k;
}

std::vector<std::vector<glm::dvec2>> syntheticViews(const Intrinsics& k, ChessboardSize b,
                                                    double square) {
  std::vector<std::vector<glm::dvec2>> views;
  const glm::dvec3 centre(0.5 * (b.cols - 1) * square, 0.5 * (b.rows - 1) * square, 0.0);
  for (int v = 0; v < 10; ++v) {
    // Eyes on a cap in front of the board (board in z = 0, camera at z < 0 looking +z).
    const double a = 0.6 * std::cos(0.7 * v), e = 0.5 * std::sin(1.3 * v);
    const double dist = 0.35 + 0.03 * v;
    const glm::dvec3 eye = centre + dist * glm::dvec3(std::sin(a) * std::cos(e), std::sin(e),
                                                      -std::cos(a) * std::cos(e));
    const Pose pose = lookFrom(eye, centre + glm::dvec3(0.01 * v, -0.005 * v, 0),
                               glm::dvec3(std::sin(0.2 * v), -1, 0));
    std::vector<glm::dvec2> corners;
    for (int r = 0; r < b.rows; ++r) {
      for (int c = 0; c < b.cols; ++c) {
        corners.push_back(projectPoint(k, pose, {c * square, r * square, 0.0}));
      }
    }
    views.push_back(corners);
  }
  return views;
}

TEST(CameraCalibration, RecoversSyntheticCameraWithinATenthOfAPercent) {
  const Intrinsics k = knownCamera();
  const ChessboardSize b{9, 6};
  const auto views = syntheticViews(k, b, 0.025);
  for (const auto& v : views) {
    for (const glm::dvec2& p : v) {
      ASSERT_TRUE(p.x > 0 && p.x < 640 && p.y > 0 && p.y < 480) << "corner off the image";
    }
  }
  const ChessboardCalibration c = calibrateFromCorners(views, b, 640, 480, 0.025);
  EXPECT_LT(std::abs(c.intrinsics.fx - k.fx) / k.fx, 1e-3) << c.intrinsics.fx;
  EXPECT_LT(std::abs(c.intrinsics.fy - k.fy) / k.fy, 1e-3) << c.intrinsics.fy;
  EXPECT_NEAR(c.intrinsics.cx, k.cx, 0.5);
  EXPECT_NEAR(c.intrinsics.cy, k.cy, 0.5);
  EXPECT_NEAR(c.intrinsics.k1, k.k1, 0.01);
  EXPECT_LT(c.rmsPx, 1e-3);  // corners are exact up to float rounding
  ASSERT_EQ(c.poses.size(), 10u);
}

TEST(CameraCalibration, RejectsTooFewViewsAndWrongCornerCounts) {
  const Intrinsics k = knownCamera();
  auto views = syntheticViews(k, {9, 6}, 0.025);
  views.resize(2);
  EXPECT_THROW(calibrateFromCorners(views, {9, 6}, 640, 480), CalibrationError);
  views = syntheticViews(k, {9, 6}, 0.025);
  views[3].pop_back();
  try {
    calibrateFromCorners(views, {9, 6}, 640, 480, 1.0, {"a", "b", "c", "d.png"});
    FAIL() << "a short corner list was accepted";
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("d.png"), std::string::npos) << e.what();
  }
}

TEST(CameraCalibration, ParsesBoardSizes) {
  EXPECT_EQ(parseChessboardSize("9x6").cols, 9);
  EXPECT_EQ(parseChessboardSize("9x6").rows, 6);
  EXPECT_THROW(parseChessboardSize("9"), CalibrationError);
  EXPECT_THROW(parseChessboardSize("9x6x2"), CalibrationError);
  EXPECT_THROW(parseChessboardSize("1x6"), CalibrationError);
  EXPECT_THROW(parseChessboardSize("ax6"), CalibrationError);
}

const std::filesystem::path kOpenCvData = "/usr/share/doc/opencv-doc/examples/data";

std::vector<std::filesystem::path> leftPhotos() {
  std::vector<std::filesystem::path> photos;
  for (int i = 1; i <= 14; ++i) {
    char name[16];
    std::snprintf(name, sizeof name, "left%02d.jpg", i);
    photos.push_back(kOpenCvData / name);  // left10.jpg is not shipped by Debian
  }
  return photos;
}

// Real photos nobody here made: Debian opencv-doc's 640x480 chessboard shots (9x6 inner
// corners). Measured here: 13 of 14 usable (left10.jpg is missing), RMS ~0.41 px.
TEST(CameraCalibration, RealChessboardPhotos) {
  if (!std::filesystem::exists(kOpenCvData / "left01.jpg")) {
    GTEST_SKIP() << "opencv-doc is not installed (.ci/install-deps.sh)";
  }
  const ChessboardCalibration c = calibrateFromChessboards(leftPhotos(), {9, 6});
  EXPECT_EQ(c.intrinsics.width, 640);
  EXPECT_EQ(c.intrinsics.height, 480);
  EXPECT_GE(c.usedCount(), 12);
  EXPECT_LT(c.rmsPx, 0.5);
  std::printf(
      "opencv-doc left*.jpg: %d photos used, fx %.2f fy %.2f cx %.2f cy %.2f, "
      "reprojection_error_px %.4f\n",
      c.usedCount(), c.intrinsics.fx, c.intrinsics.fy, c.intrinsics.cx, c.intrinsics.cy, c.rmsPx);
  // The same camera as OpenCV's own sample calibration (left_intrinsics.yml: fx ~536).
  EXPECT_NEAR(c.intrinsics.fx, 536, 15);
  bool namedMissing = false;
  for (const ChessboardImage& im : c.images) {
    if (!im.used && im.problem.find("left10.jpg") != std::string::npos) namedMissing = true;
  }
  EXPECT_TRUE(namedMissing);
}

TEST(CameraCalibration, NoBoardAndTooFewPhotosAreNamed) {
  if (!std::filesystem::exists(kOpenCvData / "left01.jpg")) GTEST_SKIP() << "no opencv-doc";
  // Asking for a board the photos do not show: every photo is named, then the error.
  try {
    calibrateFromChessboards(
        {kOpenCvData / "left01.jpg", kOpenCvData / "left02.jpg", kOpenCvData / "left03.jpg"},
        {7, 7});
    FAIL() << "a 7x7 board was found in 9x6 photos";
  } catch (const CalibrationError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("left02.jpg: no 7x7 chessboard found"), std::string::npos) << m;
    EXPECT_NE(m.find("0 of 3 photos usable"), std::string::npos) << m;
  }
  EXPECT_THROW(
      calibrateFromChessboards({kOpenCvData / "left01.jpg", kOpenCvData / "left02.jpg"}, {9, 6}),
      CalibrationError);
}

}  // namespace
}  // namespace penumbra::scene
