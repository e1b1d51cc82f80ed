// The camera's mounting (kiosk/frame_source.h, toRgba's orientation): mirrors of a frame whose
// pixels all differ, checked pixel by pixel, on odd and even sizes (the middle row and column
// stay), in the packed path and in the YUV420 path.
#include "kiosk/frame_source.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace penumbra::kiosk {
namespace {

// An RGBA8 camera frame whose pixel (x, y) holds x, y, x ^ y, 255.
CameraFrame numbered(uint32_t w, uint32_t h) {
  CameraFrame f;
  f.width = w;
  f.height = h;
  f.stride = w * 4;
  f.format = PixelFormat::kRgba8;
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      f.data.insert(f.data.end(), {uint8_t(x), uint8_t(y), uint8_t(x ^ y), 255});
    }
  }
  return f;
}

std::vector<uint8_t> converted(const CameraFrame& f, FrameOrientation o) {
  std::vector<uint8_t> rgba;
  std::string why;
  EXPECT_TRUE(toRgba(f, f.width, f.height, rgba, why, o)) << why;
  return rgba;
}

// Pixel (x, y) of `mirrored` is the pixel the mounting moves there from `plain`.
void expectMirrored(const std::vector<uint8_t>& mirrored, const std::vector<uint8_t>& plain,
                    uint32_t w, uint32_t h, FrameOrientation o) {
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      const uint32_t sx = o.mirrorX ? w - 1 - x : x, sy = o.mirrorY ? h - 1 - y : y;
      for (int c = 0; c < 4; ++c) {
        ASSERT_EQ(mirrored[(size_t(y) * w + x) * 4 + c], plain[(size_t(sy) * w + sx) * 4 + c])
            << w << "x" << h << " mirror " << o.mirrorX << o.mirrorY << " at " << x << "," << y;
      }
    }
  }
}

TEST(FrameOrientation, MirrorsMoveEveryPixelWhereTheMountingSays) {
  for (const auto& [w, h] : {std::pair<uint32_t, uint32_t>{5, 3}, {4, 6}, {1, 1}}) {
    for (int mode = 0; mode < 4; ++mode) {
      const FrameOrientation o{(mode & 1) != 0, (mode & 2) != 0};
      const CameraFrame original = numbered(w, h);
      CameraFrame frame = original;
      frame.data = converted(original, o);
      expectMirrored(frame.data, original.data, w, h, o);
      EXPECT_EQ(converted(frame, o), original.data);  // every mirror undoes itself
    }
  }
}

// The YUV420 path mirrors the same way: its mirrored conversion is the plain one, mirrored.
TEST(FrameOrientation, Yuv420IsMirroredAsItIsConverted) {
  const uint32_t w = 6, h = 4;
  CameraFrame f;
  f.width = w;
  f.height = h;
  f.stride = w;
  f.format = PixelFormat::kYuv420;
  for (uint32_t i = 0; i < w * h + 2 * (w / 2) * (h / 2); ++i) f.data.push_back(uint8_t(37 * i));
  const std::vector<uint8_t> plain = converted(f, {});
  for (int mode = 1; mode < 4; ++mode) {
    const FrameOrientation o{(mode & 1) != 0, (mode & 2) != 0};
    expectMirrored(converted(f, o), plain, w, h, o);
  }
}

}  // namespace
}  // namespace penumbra::kiosk
