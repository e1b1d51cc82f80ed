// The DRM display (platform/drm_display.h): where a frame lands on a screen and how its pixels
// are written, exactly; and the clear failures where there is no display device. The display
// itself runs on a kernel driver in the board VM (.ci/board-vm-quick: virtio-gpu).
#ifdef PENUMBRA_HAVE_DRM
#include "platform/drm_display.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace penumbra::platform {
namespace {

TEST(DrmDisplay, FitKeepsTheAspectAndCentresTheFrame) {
  // Height-bound: 2.25x.
  const ScreenFit wide = fitFrame(640, 480, 1920, 1080);
  EXPECT_EQ(wide.x, 240u);
  EXPECT_EQ(wide.y, 0u);
  EXPECT_EQ(wide.width, 1440u);
  EXPECT_EQ(wide.height, 1080u);
  EXPECT_EQ(wide.sourceColumn.front(), 0u);
  EXPECT_EQ(wide.sourceColumn.back(), 639u);
  EXPECT_EQ(wide.sourceRow.back(), 479u);
  EXPECT_TRUE(std::is_sorted(wide.sourceColumn.begin(), wide.sourceColumn.end()));
  // Scaling up shows every frame column, each 2 or 3 screen pixels wide.
  for (uint32_t c = 0; c < 640; ++c) {
    const auto n = std::count(wide.sourceColumn.begin(), wide.sourceColumn.end(), c);
    EXPECT_TRUE(n == 2 || n == 3) << "column " << c << " shown " << n << " times";
  }
  // An exact 2x: every frame pixel is a 2x2 block.
  const ScreenFit twice = fitFrame(640, 480, 1280, 960);
  EXPECT_EQ(twice.x, 0u);
  EXPECT_EQ(twice.y, 0u);
  for (uint32_t i = 0; i < 1280; ++i) EXPECT_EQ(twice.sourceColumn[i], i / 2);
  for (uint32_t i = 0; i < 960; ++i) EXPECT_EQ(twice.sourceRow[i], i / 2);
  // A screen smaller than the frame: scaled down, width from the height bound.
  const ScreenFit small = fitFrame(640, 480, 320, 200);
  EXPECT_EQ(small.height, 200u);
  EXPECT_EQ(small.width, 266u);  // 640 * 200 / 480, rounded down
  EXPECT_EQ(small.x, 27u);
  EXPECT_LT(small.sourceColumn.back(), 640u);
  // Width-bound: a tall screen.
  const ScreenFit tall = fitFrame(640, 480, 800, 1280);
  EXPECT_EQ(tall.width, 800u);
  EXPECT_EQ(tall.height, 600u);
  EXPECT_EQ(tall.y, 340u);
  // The same size: the identity.
  const ScreenFit same = fitFrame(480, 360, 480, 360);
  for (uint32_t i = 0; i < 480; ++i) EXPECT_EQ(same.sourceColumn[i], i);
  EXPECT_THROW(fitFrame(0, 480, 640, 480), std::invalid_argument);
}

TEST(DrmDisplay, BlitWritesXrgbInsideTheFitAndLeavesTheBars) {
  // A 2x2 frame (red, blue / green, grey) on an 8x4 screen with padded rows: 2x at x = 2.
  const std::vector<uint8_t> frame{255, 0, 0, 255, 0, 0, 255, 255, 0, 255, 0, 255, 9, 8, 7, 255};
  const ScreenFit fit = fitFrame(2, 2, 8, 4);
  ASSERT_EQ(fit.x, 2u);
  ASSERT_EQ(fit.y, 0u);
  ASSERT_EQ(fit.width, 4u);
  ASSERT_EQ(fit.height, 4u);
  const uint32_t pitch = 8 * 4 + 8;
  std::vector<uint8_t> screen(pitch * 4, 0x55);
  blitFrame(frame.data(), 2, fit, screen.data(), pitch);
  const auto pixel = [&](uint32_t x, uint32_t y) {
    const uint8_t* p = &screen[y * pitch + x * 4];
    return std::vector<uint8_t>(p, p + 4);
  };
  // XRGB8888 in memory: B, G, R, X.
  const std::vector<uint8_t> red{0, 0, 255, 255}, blue{255, 0, 0, 255}, green{0, 255, 0, 255},
      grey{7, 8, 9, 255}, bar(4, 0x55);
  for (uint32_t y = 0; y < 4; ++y) {
    EXPECT_EQ(pixel(2, y), y < 2 ? red : green) << "row " << y;
    EXPECT_EQ(pixel(3, y), y < 2 ? red : green) << "row " << y;
    EXPECT_EQ(pixel(4, y), y < 2 ? blue : grey) << "row " << y;
    EXPECT_EQ(pixel(5, y), y < 2 ? blue : grey) << "row " << y;
    for (uint32_t x : {0u, 1u, 6u, 7u}) EXPECT_EQ(pixel(x, y), bar) << x << "," << y;
    // The row padding is the driver's: untouched.
    EXPECT_TRUE(std::all_of(screen.begin() + y * pitch + 32, screen.begin() + (y + 1) * pitch,
                            [](uint8_t v) { return v == 0x55; }));
  }
}

std::string failure(const std::filesystem::path& device) {
  try {
    DrmDisplay d(device, 640, 480);
  } catch (const HardwareUnavailable& e) {
    return e.what();
  }
  return "no failure";
}

TEST(DrmDisplay, NoDeviceFailsNamingIt) {
  EXPECT_EQ(failure("/dev/dri-penumbra-absent/card0"),
            "display: /dev/dri-penumbra-absent/card0: No such file or directory");
  const std::string notKms = failure("/dev/null");
  EXPECT_EQ(notKms.rfind("display: /dev/null: not a display (KMS) device", 0), 0u) << notKms;
  if (std::filesystem::exists("/dev/dri")) {
    GTEST_SKIP() << "this machine has /dev/dri: the search for a screen is the board VM's test";
  }
  EXPECT_EQ(failure(""), "display: /dev/dri: No such file or directory (no display driver)");
}

}  // namespace
}  // namespace penumbra::platform
#endif
