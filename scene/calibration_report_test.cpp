// calibrateCamera on the bundled marks (data/calibration): the vanishing-point method with
// the corner refit, its JSON, the file written through a temporary, and requests naming no
// method or both refused.
#include "scene/calibration_report.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "tests/scratch_dir.h"

namespace penumbra::scene {
namespace {

const std::filesystem::path kData = std::filesystem::path(PENUMBRA_DATA_DIR) / "calibration";

TEST(CalibrationReport, VanishingPointsWithCornerRefit) {
  CalibrationRequest q;
  q.vanishing = (kData / "vanishing-marks.json").string();
  q.corners = (kData / "room-corners.json").string();
  const CalibrationReport r = calibrateCamera(q);
  ASSERT_TRUE(r.vanishing.has_value());
  EXPECT_FALSE(r.chessboard.has_value());
  ASSERT_TRUE(r.corners.has_value());
  EXPECT_EQ(r.intrinsics.fx, r.vanishing->intrinsics.fx);
  EXPECT_EQ(r.json["method"], "vanishing");
  EXPECT_EQ(r.json["intrinsics"]["fx"], r.intrinsics.fx);
  EXPECT_EQ(r.json["pose"]["camera_position"].size(), 3u);
  EXPECT_EQ(r.json["pose"]["rotation_world_to_camera"].size(), 9u);
  EXPECT_EQ(r.json["corners_reprojection_error_px"], r.corners->rmsPx);
  // The two poses agree: the marks come from one synthetic view.
  const glm::dvec3 a = r.vanishing->pose.centre(), b = r.corners->pose.centre();
  EXPECT_LT(glm::length(a - b), 0.1);

  const std::filesystem::path dir = test::scratchPath("calib");
  std::filesystem::create_directories(dir);
  writeJsonFile(dir / "c.json", r.json);
  // core::writeFileReplacing's temporary is gone: the folder holds the result alone.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
  EXPECT_EQ(nlohmann::json::parse(std::ifstream(dir / "c.json")), r.json);
  std::filesystem::remove_all(dir);
}

TEST(CalibrationReport, ExactlyOneMethod) {
  CalibrationRequest none;
  EXPECT_THROW(calibrateCamera(none), std::invalid_argument);
  CalibrationRequest both;
  both.chessboard = "9x6";
  both.images = {"a.png"};
  both.vanishing = (kData / "vanishing-marks.json").string();
  EXPECT_THROW(calibrateCamera(both), std::invalid_argument);
  CalibrationRequest noImages;
  noImages.chessboard = "9x6";
  EXPECT_THROW(calibrateCamera(noImages), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::scene
