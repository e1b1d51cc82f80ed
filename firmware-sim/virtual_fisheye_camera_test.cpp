// The simulated environment camera (firmware-sim/virtual_fisheye_camera.h): EXR sequences
// written with OpenCV in the test's scratch folder, played on the virtual clock.
#ifdef PENUMBRA_HAVE_FOOTAGE
#include "firmware-sim/virtual_fisheye_camera.h"

#include <gtest/gtest.h>

#include <fstream>
#include <limits>
#include <opencv2/imgcodecs.hpp>

#include "firmware-sim/footage.h"
#include "tests/scratch_dir.h"

namespace penumbra::firmware_sim {
namespace {

namespace fs = std::filesystem;

// A 6 × 4 float BGR frame whose red is k + 0.5 (green 2, blue −0.01: DWAB-like ringing).
cv::Mat exrFrame(int k, int w = 6, int h = 4) {
  return cv::Mat(h, w, CV_32FC3, cv::Scalar(-0.01, 2.0, k + 0.5));
}

class FisheyeCamera : public ::testing::Test {
 protected:
  void SetUp() override { fs::create_directories(dir_); }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& name, const cv::Mat& m) {
    ASSERT_TRUE(cv::imwrite((dir_ / name).string(), m)) << name;
  }
  std::string refusal(const fs::path& source) {
    try {
      loadExrSequence(source);
    } catch (const FootageError& e) {
      return e.what();
    }
    return "accepted";
  }
  const fs::path dir_ = test::scratchPath("fisheye-camera");
};

TEST_F(FisheyeCamera, PlaysAnExrSequenceInNameOrderOnTheVirtualClock) {
  for (int k : {2, 0, 1}) write("env_000" + std::to_string(k) + ".exr", exrFrame(k));
  std::ofstream(dir_ / "notes.txt") << "not an EXR: ignored in a folder";
  const ExrSequence sequence = loadExrSequence(dir_);
  ASSERT_EQ(sequence.frames.size(), 3u);
  EXPECT_EQ(sequence.clampedNegative, 3u * 6 * 4);  // every blue sample was −0.01
  for (int k = 0; k < 3; ++k) {
    EXPECT_FLOAT_EQ(sequence.frames[k].pixel(5, 3)[0],
                    float(k) + 0.5f);  // R (OpenCV's BGR swapped)
    EXPECT_FLOAT_EQ(sequence.frames[k].pixel(5, 3)[1], 2.0f);
    EXPECT_FLOAT_EQ(sequence.frames[k].pixel(5, 3)[2], 0.0f);
  }
  VirtualFisheyeCamera camera(sequence.frames, 100);
  core::ImageF frame;
  uint64_t k = 0;
  EXPECT_FALSE(camera.grab(-1, frame, k));
  ASSERT_TRUE(camera.grab(0, frame, k));
  EXPECT_EQ(k, 0u);
  EXPECT_FALSE(camera.grab(99, frame, k));  // nothing newer
  ASSERT_TRUE(camera.grab(450, frame, k));  // frames 1–3 missed: the newest is 4
  EXPECT_EQ(k, 4u);
  EXPECT_FLOAT_EQ(frame.pixel(0, 0)[0], 1.5f);  // 4 mod 3 = sequence frame 1
  EXPECT_NE(camera.describe().find("3 HDR frames of 6x4"), std::string::npos);
}

TEST_F(FisheyeCamera, BadSequencesAreRefusedNamingTheFile) {
  EXPECT_NE(refusal(dir_ / "*.exr").find("no file matches"), std::string::npos);
  write("a.exr", exrFrame(0));
  write("b.exr", exrFrame(1, 8, 4));
  EXPECT_NE(refusal(dir_).find("b.exr: 8x4, but"), std::string::npos) << refusal(dir_);
  fs::remove(dir_ / "b.exr");
  cv::Mat nan = exrFrame(1);
  nan.at<cv::Vec3f>(1, 1)[2] = std::numeric_limits<float>::quiet_NaN();
  write("b.exr", nan);
  EXPECT_NE(refusal(dir_).find("b.exr: 1 samples are NaN"), std::string::npos) << refusal(dir_);
  std::ofstream(dir_ / "b.exr") << "not an exr";
  EXPECT_NE(refusal(dir_).find("b.exr: not a readable EXR"), std::string::npos) << refusal(dir_);
  EXPECT_THROW(VirtualFisheyeCamera({}, 100), std::invalid_argument);
  EXPECT_THROW(VirtualFisheyeCamera({core::ImageF(2, 2)}, 0), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::firmware_sim
#endif
