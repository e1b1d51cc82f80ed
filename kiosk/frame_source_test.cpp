// The camera's mounting (kiosk/frame_source.h, orient): mirrors of a frame whose pixels all
// differ, checked pixel by pixel, on odd and even sizes (the middle row and column stay).
#include "kiosk/frame_source.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace penumbra::kiosk {
namespace {

// Pixel (x, y) holds x, y, x ^ y, 255.
std::vector<uint8_t> numbered(uint32_t w, uint32_t h) {
  std::vector<uint8_t> rgba;
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      rgba.insert(rgba.end(), {uint8_t(x), uint8_t(y), uint8_t(x ^ y), 255});
    }
  }
  return rgba;
}

TEST(FrameOrientation, MirrorsMoveEveryPixelWhereTheMountingSays) {
  for (const auto& [w, h] : {std::pair<uint32_t, uint32_t>{5, 3}, {4, 6}, {1, 1}}) {
    for (int mode = 0; mode < 4; ++mode) {
      const FrameOrientation o{(mode & 1) != 0, (mode & 2) != 0};
      const std::vector<uint8_t> original = numbered(w, h);
      std::vector<uint8_t> frame = original;
      orient(frame, w, h, o);
      for (uint32_t y = 0; y < h; ++y) {
        for (uint32_t x = 0; x < w; ++x) {
          const uint32_t sx = o.mirrorX ? w - 1 - x : x, sy = o.mirrorY ? h - 1 - y : y;
          for (int c = 0; c < 4; ++c) {
            ASSERT_EQ(frame[(size_t(y) * w + x) * 4 + c], original[(size_t(sy) * w + sx) * 4 + c])
                << w << "x" << h << " mode " << mode << " at " << x << "," << y;
          }
        }
      }
      orient(frame, w, h, o);  // every mirror undoes itself
      EXPECT_EQ(frame, original);
    }
  }
}

}  // namespace
}  // namespace penumbra::kiosk
