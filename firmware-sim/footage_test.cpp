// Footage for the simulated camera (firmware-sim/footage.h): a small video written with
// OpenCV's VideoWriter and PNG sequences in the test's scratch folder, and bad files.
#ifdef PENUMBRA_HAVE_FOOTAGE
#include "firmware-sim/footage.h"

#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "tests/scratch_dir.h"

namespace penumbra::firmware_sim {
namespace {

namespace fs = std::filesystem;

// Frame k: a flat BGR colour that changes with k.
cv::Mat colourFrame(int k, int w, int h) {
  return cv::Mat(h, w, CV_8UC3, cv::Scalar(255 - 20 * k, 100, 20 * k));
}

class Footage : public ::testing::Test {
 protected:
  void SetUp() override { fs::create_directories(dir_); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string refusal(const fs::path& source, uint32_t w = 32, uint32_t h = 24) {
    try {
      loadFootage(source, w, h);
    } catch (const FootageError& e) {
      return e.what();
    }
    return "accepted";
  }
  const fs::path dir_ = test::scratchPath("footage");
};

TEST_F(Footage, VideoFileIsReadResizedAndKeptInOrder) {
  const fs::path video = dir_ / "clip.avi";
  {
    cv::VideoWriter w(video.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 30,
                      cv::Size(64, 48));
    ASSERT_TRUE(w.isOpened());
    for (int k = 0; k < 10; ++k) w.write(colourFrame(k, 64, 48));
  }
  const auto frames = loadFootage(video, 32, 24);
  ASSERT_EQ(frames.size(), 10u);
  for (int k = 0; k < 10; ++k) {
    const uint8_t* centre = &frames[size_t(k)][(12 * 32 + 16) * 4];
    // RGBA; MJPEG is lossy, a few codes off.
    EXPECT_NEAR(centre[0], 20 * k, 6) << "frame " << k;
    EXPECT_NEAR(centre[1], 100, 6) << "frame " << k;
    EXPECT_NEAR(centre[2], 255 - 20 * k, 6) << "frame " << k;
    EXPECT_EQ(centre[3], 255);
  }
}

TEST_F(Footage, ImageSequenceFromAFolderOrAGlobInNameOrder) {
  for (int k = 4; k >= 0; --k) {
    cv::imwrite((dir_ / ("shot-0" + std::to_string(k) + ".png")).string(), colourFrame(k, 32, 24));
  }
  std::ofstream(dir_ / "notes.txt") << "not an image";
  const auto all = loadFootage(dir_, 32, 24);
  ASSERT_EQ(all.size(), 5u);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(all[size_t(k)][0], 20 * k) << "frame " << k;  // exact
  const auto some = loadFootage(dir_ / "shot-0[1-3].png", 32, 24);
  ASSERT_EQ(some.size(), 3u);
  EXPECT_EQ(some[0][0], 20);
}

TEST_F(Footage, BadFilesAreRefusedByName) {
  EXPECT_NE(refusal(dir_ / "absent.mp4").find("absent.mp4: no such file"), std::string::npos);
  EXPECT_NE(refusal(dir_ / "*.png").find("*.png: no file matches"), std::string::npos);
  std::ofstream(dir_ / "clip.mp4") << "this is not a video";
  const std::string notVideo = refusal(dir_ / "clip.mp4");
  EXPECT_NE(notVideo.find((dir_ / "clip.mp4").string() + ": "), std::string::npos) << notVideo;
  // A truncated PNG in a sequence is named.
  cv::imwrite((dir_ / "a.png").string(), colourFrame(0, 32, 24));
  cv::imwrite((dir_ / "b.png").string(), colourFrame(1, 32, 24));
  fs::resize_file(dir_ / "b.png", 40);
  const std::string truncated = refusal(dir_ / "?.png");
  EXPECT_NE(truncated.find("b.png: not a readable image"), std::string::npos) << truncated;
  // Another camera's geometry: square footage for a 4:3 view.
  cv::imwrite((dir_ / "square.png").string(), colourFrame(0, 24, 24));
  EXPECT_NE(refusal(dir_ / "square.png").find("does not have the aspect ratio of the 32x24 view"),
            std::string::npos);
  // Frames of two sizes in one sequence.
  cv::imwrite((dir_ / "s1.png").string(), colourFrame(0, 32, 24));
  cv::imwrite((dir_ / "s2.png").string(), colourFrame(0, 64, 48));
  EXPECT_NE(refusal(dir_ / "s?.png").find("s2.png: 64x48, but"), std::string::npos);
  // Too long for the memory cap.
  try {
    loadFootage(dir_ / "s1.png", 32, 24, 100);
    FAIL();
  } catch (const FootageError& e) {
    EXPECT_NE(std::string(e.what()).find("footage longer than"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace penumbra::firmware_sim
#endif
