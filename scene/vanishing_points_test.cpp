#include "scene/vanishing_points.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "scene/calibration_test_util.h"
#include "tests/scratch_dir.h"

namespace penumbra::scene {
namespace {

using testutil::lookFrom;

// A 640x480 camera with f = 700 px, principal point at the centre, looking into a room
// corner from (3, 1.6, 4): the floor edges along x and z give the marks.
struct Synthetic {
  Intrinsics k;
  Pose pose;
  VanishingMarks marks;
};

Synthetic synthetic() {
  Synthetic s;
  s.k.width = 640;
  s.k.height = 480;
  s.k.fx = s.k.fy = 700;
  s.k.cx = 319.5;
  s.k.cy = 239.5;
  s.pose = lookFrom({3.0, 1.6, 4.0}, {0.4, 0.5, 0.3});
  auto px = [&](const glm::dvec3& w) { return projectPoint(s.k, s.pose, w); };
  VanishingMarks& m = s.marks;
  m.source = "synthetic.json";
  m.width = 640;
  m.height = 480;
  // Two lines along x (floor edge z = 0, and the skirting at height 1) and two along z.
  m.lines[0] = std::array<ImageLine, 2>{ImageLine{px({0, 0, 0}), px({2, 0, 0})},
                                        ImageLine{px({0, 1, 0}), px({2.5, 1, 0})}};
  m.lines[2] = std::array<ImageLine, 2>{ImageLine{px({0, 0, 0}), px({0, 0, 2})},
                                        ImageLine{px({0, 1.2, 0.2}), px({0, 1.2, 2.2})}};
  m.origin = px({0, 0, 0});
  m.axisPoints[0] = AxisPoint{px({1.5, 0, 0}), 1.5};
  m.axisPoints[2] = AxisPoint{px({0, 0, 2.0}), 2.0};
  m.axisPoints[1] = AxisPoint{px({0, 1.0, 0}), 1.0};
  return s;
}

TEST(VanishingPoints, RecoversSyntheticCamera) {
  const Synthetic s = synthetic();
  const VanishingCalibration c = calibrateFromVanishingPoints(s.marks);
  EXPECT_EQ(c.markedAxes[0], 0);
  EXPECT_EQ(c.markedAxes[1], 2);
  EXPECT_EQ(c.derivedAxis, 1);
  EXPECT_NEAR(c.intrinsics.fx, 700.0, 700.0 * 1e-6);
  EXPECT_NEAR(c.intrinsics.cx, 319.5, 1e-12);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(c.pose.rotation[i][j], s.pose.rotation[i][j], 1e-9);
  }
  EXPECT_LT(glm::length(c.pose.centre() - s.pose.centre()), 1e-6);
  EXPECT_LT(c.rmsPx, 1e-6);
  ASSERT_EQ(c.residualsPx.size(), 4u);  // origin, x, y, z
}

TEST(VanishingPoints, ReprojectionErrorGrowsWithMarkNoise) {
  Synthetic s = synthetic();
  s.marks.axisPoints[1]->image += glm::dvec2(3.0, -4.0);  // the y mark is 5 px off
  const VanishingCalibration c = calibrateFromVanishingPoints(s.marks);
  EXPECT_GT(c.rmsPx, 1.0);
  EXPECT_LT(c.rmsPx, 5.0);
}

TEST(VanishingPoints, ParallelLinesRejected) {
  Synthetic s = synthetic();
  (*s.marks.lines[0])[1] = ImageLine{{10, 400}, {600, 380}};
  (*s.marks.lines[0])[0] = ImageLine{{10, 300}, {600, 280}};
  try {
    calibrateFromVanishingPoints(s.marks);
    FAIL() << "parallel lines accepted";
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("synthetic.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("vanishing_lines.x"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("infinity"), std::string::npos) << e.what();
  }
}

TEST(VanishingPoints, NonPositiveFocalSquaredRejected) {
  Synthetic s = synthetic();
  // Both vanishing points to the right of the centre: (v - c).(v' - c) > 0.
  s.marks.lines[0] =
      std::array<ImageLine, 2>{ImageLine{{0, 200}, {500, 240}}, ImageLine{{0, 300}, {500, 260}}};
  s.marks.lines[2] =
      std::array<ImageLine, 2>{ImageLine{{0, 100}, {500, 200}}, ImageLine{{0, 400}, {500, 300}}};
  try {
    calibrateFromVanishingPoints(s.marks);
    FAIL() << "f^2 <= 0 accepted";
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("f^2"), std::string::npos) << e.what();
  }
}

TEST(VanishingPoints, ZeroLengthLineAndBadAxisPointsRejected) {
  Synthetic s = synthetic();
  (*s.marks.lines[2])[1].b = (*s.marks.lines[2])[1].a;
  EXPECT_THROW(calibrateFromVanishingPoints(s.marks), CalibrationError);
  s = synthetic();
  s.marks.axisPoints[0]->image = s.marks.origin;
  EXPECT_THROW(calibrateFromVanishingPoints(s.marks), CalibrationError);
  s = synthetic();
  // Perpendicular to the direction of the x vanishing point: the sign is undecidable.
  const glm::dvec2 toV =
      vanishingPoint((*s.marks.lines[0])[0], (*s.marks.lines[0])[1], "x") - s.marks.origin;
  s.marks.axisPoints[0]->image = s.marks.origin + 50.0 * glm::normalize(glm::dvec2(-toV.y, toV.x));
  EXPECT_THROW(calibrateFromVanishingPoints(s.marks), CalibrationError);
  s = synthetic();
  s.marks.axisPoints[2].reset();
  EXPECT_THROW(calibrateFromVanishingPoints(s.marks), CalibrationError);
}

class MarksFile : public ::testing::Test {
 protected:
  std::filesystem::path dir = test::scratchPath("vp");
  void SetUp() override { std::filesystem::create_directories(dir); }
  void TearDown() override { std::filesystem::remove_all(dir); }
  std::filesystem::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return dir / name;
  }
  // Expects loading (and, if it loads, calibrating) `text` to fail naming the file and
  // `field`.
  void expectError(const std::string& text, const std::string& field) {
    const auto path = write("bad-marks.json", text);
    try {
      calibrateFromVanishingPoints(loadVanishingMarks(path));
      ADD_FAILURE() << "accepted: " << text;
    } catch (const CalibrationError& e) {
      EXPECT_NE(std::string(e.what()).find("bad-marks.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
};

TEST_F(MarksFile, BundledExampleCalibrates) {
  const auto path =
      std::filesystem::path(PENUMBRA_DATA_DIR) / "calibration" / "vanishing-marks.json";
  const VanishingCalibration c = calibrateFromVanishingPoints(loadVanishingMarks(path));
  EXPECT_GT(c.intrinsics.fx, 100);
  EXPECT_LT(c.rmsPx, 2.0);
}

TEST_F(MarksFile, MalformedFilesNameTheField) {
  const std::string good = R"({"image": {"width": 640, "height": 480},
    "vanishing_lines": {"x": [[[10, 300], [300, 280]], [[10, 100], [300, 150]]],
                        "z": [[[400, 300], [600, 350]], [[400, 100], [600, 60]]]},
    "origin": [350, 290],
    "axis_points": {"x": {"image": [200, 294], "distance": 1},
                    "z": {"image": [500, 320], "distance": 1}}})";
  auto replace = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  expectError("{ not json", "line 1: ");
  expectError(replace(R"("width": 640)", R"("width": "640")"), "image.width");
  expectError(replace(R"("origin": [350, 290])", R"("origin": [350, 1e999])"), "1e999");
  expectError(replace(R"("origin": [350, 290])", R"("origin": [350])"), "origin");
  expectError(replace(R"("distance": 1})", R"("distance": -1})"), "axis_points.x.distance");
  expectError(replace(R"("origin")", R"("orign")"), "orign");
  expectError(replace(R"([[10, 100], [300, 150]])", R"([[10, 320], [300, 300]])"),
              "vanishing_lines.x");
  expectError(replace(R"("z": [[[400)", R"("y": [[[400)"), "axis_points.y");
}

}  // namespace
}  // namespace penumbra::scene
