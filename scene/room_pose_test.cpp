#include "scene/room_pose.h"

#include <gtest/gtest.h>

#include "scene/calibration_test_util.h"

namespace penumbra::scene {
namespace {

Intrinsics camera640() {
  Intrinsics k;
  k.width = 640;
  k.height = 480;
  k.fx = k.fy = 420;
  k.cx = 321;
  k.cy = 238;
  k.k1 = -0.1;
  return k;
}

// Corners of a 5 x 2.7 x 4 m room's floor and back wall and of a desk, seen from a kiosk
// camera high up at the open end of the showroom.
std::vector<CornerMark> syntheticMarks(const Intrinsics& k, const Pose& pose) {
  const std::vector<glm::dvec3> world = {{0, 0, 0}, {5, 0, 0}, {0, 2.7, 0},    {5, 2.7, 0},
                                         {0, 0, 4}, {5, 0, 4}, {1.2, 0.75, 1}, {2.4, 0.75, 1.8}};
  std::vector<CornerMark> marks;
  for (size_t i = 0; i < world.size(); ++i) {
    marks.push_back({"corner " + std::to_string(i), world[i], projectPoint(k, pose, world[i])});
  }
  return marks;
}

TEST(RoomPose, RecoversSyntheticPose) {
  const Intrinsics k = camera640();
  const Pose truth = testutil::lookFrom({6.5, 2.5, 7.5}, {2.5, 0.9, 2.0});
  std::vector<CornerMark> marks = syntheticMarks(k, truth);
  for (const CornerMark& m : marks) {
    ASSERT_TRUE(m.image.x > 0 && m.image.x < 640 && m.image.y > 0 && m.image.y < 480) << m.name;
  }
  const PoseFit fit = fitPose(k, marks);
  EXPECT_LT(glm::length(fit.pose.centre() - truth.centre()), 1e-6);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(fit.pose.rotation[i][j], truth.rotation[i][j], 1e-8);
  }
  EXPECT_LT(fit.rmsPx, 1e-6);
  // Only four marks (the floor rectangle, coplanar) still determine the pose.
  marks.erase(marks.begin() + 2);
  marks.erase(marks.begin() + 2);
  marks.resize(4);
  const PoseFit four = fitPose(k, marks);
  EXPECT_LT(glm::length(four.pose.centre() - truth.centre()), 1e-4);
}

TEST(RoomPose, NoisyMarksGiveTheirReprojectionError) {
  const Intrinsics k = camera640();
  const Pose truth = testutil::lookFrom({6.5, 2.5, 7.5}, {2.5, 0.9, 2.0});
  std::vector<CornerMark> marks = syntheticMarks(k, truth);
  for (size_t i = 0; i < marks.size(); ++i) {
    marks[i].image += glm::dvec2(i % 2 ? 1.0 : -1.0, i % 3 ? 0.5 : -0.5);
  }
  const PoseFit fit = fitPose(k, marks);
  EXPECT_GT(fit.rmsPx, 0.3);
  EXPECT_LT(fit.rmsPx, 1.2);
  EXPECT_LT(glm::length(fit.pose.centre() - truth.centre()), 0.1);
  // The renderer's camera looks the same way.
  const Camera cam = toCamera(k, fit.pose, 0.05, 20);
  const glm::dvec3 fwd = glm::normalize(cam.target - cam.eye);
  EXPECT_GT(glm::dot(fwd, glm::normalize(glm::dvec3(2.5, 0.9, 2.0) - glm::dvec3(6.5, 2.5, 7.5))),
            0.999);
}

TEST(RoomPose, DegenerateMarksRejected) {
  const Intrinsics k = camera640();
  const Pose truth = testutil::lookFrom({6.5, 2.5, 7.5}, {2.5, 0.9, 2.0});
  std::vector<CornerMark> marks = syntheticMarks(k, truth);
  std::vector<CornerMark> three(marks.begin(), marks.begin() + 3);
  EXPECT_THROW(fitPose(k, three), CalibrationError);
  std::vector<CornerMark> line;
  for (int i = 0; i < 5; ++i) {
    const glm::dvec3 w(i * 1.0, 0, 0);
    line.push_back({"edge", w, projectPoint(k, truth, w)});
  }
  EXPECT_THROW(fitPose(k, line, "line.json"), CalibrationError);
  marks[1].image.x = std::numeric_limits<double>::quiet_NaN();
  try {
    fitPose(k, marks, "marks.json");
    FAIL() << "NaN accepted";
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("marks.json: corner 1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace penumbra::scene
