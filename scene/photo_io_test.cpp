#include "scene/photo_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "scene/camera_intrinsics.h"
#include "tests/scratch_dir.h"

namespace penumbra::scene {
namespace {

TEST(PhotoIo, ReadsARealJpegAsRgb) {
  const std::filesystem::path photo = "/usr/share/doc/opencv-doc/examples/data/left01.jpg";
  if (!std::filesystem::exists(photo)) GTEST_SKIP() << "no opencv-doc";
  const core::Image8 p = readPhotoRgb8(photo);
  EXPECT_EQ(p.width, 640);
  EXPECT_EQ(p.height, 480);
  EXPECT_EQ(p.channels, 3u);
  EXPECT_EQ(p.name, "left01.jpg");  // the file name, for the capture's error messages
  ASSERT_EQ(p.pixels.size(), 640u * 480u * 3u);
  // A grey chessboard photo: the three channels agree and the board spans dark to light.
  uint8_t lo = 255, hi = 0;
  for (size_t i = 0; i < p.pixels.size(); i += 3) {
    EXPECT_EQ(p.pixels[i], p.pixels[i + 1]);
    lo = std::min(lo, p.pixels[i]);
    hi = std::max(hi, p.pixels[i]);
  }
  EXPECT_LT(lo, 60);
  EXPECT_GT(hi, 200);
}

TEST(PhotoIo, MissingAndUndecodableFilesNamed) {
  const auto dir = test::scratchPath("photo");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "junk.jpg") << "not a jpeg";
  try {
    readPhotoRgb8(dir / "junk.jpg");
    FAIL();
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("junk.jpg: cannot decode"), std::string::npos);
  }
  EXPECT_THROW(readPhotoRgb8(dir / "absent.png"), CalibrationError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace penumbra::scene
