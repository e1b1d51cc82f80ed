// Frame buffers mapped as a capture backend maps them (a memfd stands in for the dma-buf:
// the same mmap path), packed and converted to the kiosk's RGBA8.
#include "platform/camera_buffers.h"

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include "platform/hardware.h"

namespace penumbra::platform {
namespace {

// A memfd holding `bytes`, closed with the test.
class MemFd {
 public:
  explicit MemFd(const std::vector<uint8_t>& bytes) : fd_(::memfd_create("penumbra-frame", 0)) {
    EXPECT_GE(fd_, 0);
    EXPECT_EQ(::write(fd_, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
  }
  ~MemFd() { ::close(fd_); }
  int fd() const { return fd_; }

 private:
  int fd_;
};

// One packed plane, bytes B, G, R (and X when `bpp` is 4) per pixel, rows padded to `stride`
// as ISPs and pipelines align them: mapped, packed and converted. Blue is 10·x, green 20·y,
// red 200; the padding bytes (0xEE) must not show.
void expectPackedPlaneConverts(kiosk::PixelFormat format, uint32_t bpp, uint32_t w, uint32_t h,
                               uint32_t stride) {
  std::vector<uint8_t> bytes(size_t{stride} * h, 0xEE);
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      uint8_t* p = &bytes[y * stride + x * bpp];
      p[0] = static_cast<uint8_t>(10 * x), p[1] = static_cast<uint8_t>(20 * y), p[2] = 200;
      if (bpp == 4) p[3] = 0;
    }
  }
  MemFd mem(bytes);
  MappedFrameBuffer mapped({{mem.fd(), 0, bytes.size()}});
  kiosk::CameraFrame frame;
  std::string why;
  ASSERT_TRUE(packFrame(mapped.planes(), format, w, h, stride, frame, why)) << why;
  std::vector<uint8_t> rgba;
  ASSERT_TRUE(toRgba(frame, w, h, rgba, why)) << why;
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      const uint8_t* q = &rgba[(y * w + x) * 4];
      EXPECT_EQ(q[0], 200);
      EXPECT_EQ(q[1], 20 * y);
      EXPECT_EQ(q[2], 10 * x);
      EXPECT_EQ(q[3], 255);
    }
  }
}

// Why packFrame refuses one plane of `bytes` bytes at that size ("" if it packs it).
std::string packRefusal(kiosk::PixelFormat format, size_t bytes, uint32_t w, uint32_t h,
                        uint32_t stride) {
  MemFd mem{std::vector<uint8_t>(bytes)};
  MappedFrameBuffer mapped({{mem.fd(), 0, bytes}});
  kiosk::CameraFrame frame;
  std::string why;
  return packFrame(mapped.planes(), format, w, h, stride, frame, why) ? "" : why;
}

TEST(CameraBuffers, Xrgb8888PlaneWithPaddedStride) {
  expectPackedPlaneConverts(kiosk::PixelFormat::kXrgb8888, 4, 6, 4, 32);  // 8 bytes of padding
  // A plane shorter than stride × height is refused, naming the sizes.
  EXPECT_EQ(packRefusal(kiosk::PixelFormat::kXrgb8888, 128, 6, 5, 32),
            "XRGB8888 plane 0: 128 bytes, 160 needed");
}

// libcamera's RGB888 (the vimc test camera's only RGB output) is 24-bit B, G, R in memory.
TEST(CameraBuffers, Rgb888PlaneWithPaddedStride) {
  expectPackedPlaneConverts(kiosk::PixelFormat::kBgr8, 3, 5, 3, 16);  // 1 byte of padding
  // A stride shorter than a row of pixels is refused, naming both.
  EXPECT_EQ(packRefusal(kiosk::PixelFormat::kBgr8, 48, 6, 3, 16), "BGR8 stride 16 < 3 x width 6");
}

TEST(CameraBuffers, Yuv420PlanesSharingOneFdConvertWithTheJpegMatrix) {
  // Three planes in one buffer at increasing offsets, as libcamera allocates YUV420. The
  // left half is grey (U = V = 128 → R = G = B = Y); the right half holds JFIF's pure red
  // (Y 76, U 85, V 255) → (254, 0, 0) and pure blue (Y 29, U 255, V 107) → (0, 0, 254)
  // in the lower rows: the matrix's own rounding of the 8-bit triple.
  constexpr uint32_t w = 4, h = 4, stride = 8;
  const size_t ySize = stride * h, cSize = (stride / 2) * (h / 2);
  std::vector<uint8_t> bytes(ySize + 2 * cSize + 100, 0);  // + a tail other planes may use
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) bytes[y * stride + x] = x < 2 ? 90 : (y < 2 ? 76 : 29);
  }
  uint8_t* u = &bytes[ySize];
  uint8_t* v = &bytes[ySize + cSize];
  for (uint32_t cy = 0; cy < 2; ++cy) {
    u[cy * 4 + 0] = v[cy * 4 + 0] = 128;
    u[cy * 4 + 1] = cy == 0 ? 85 : 255;
    v[cy * 4 + 1] = cy == 0 ? 255 : 107;
  }
  MemFd mem(bytes);
  MappedFrameBuffer mapped(
      {{mem.fd(), 0, ySize}, {mem.fd(), ySize, cSize}, {mem.fd(), ySize + cSize, cSize}});
  kiosk::CameraFrame frame;
  std::string why;
  ASSERT_TRUE(packFrame(mapped.planes(), kiosk::PixelFormat::kYuv420, w, h, stride, frame, why))
      << why;
  std::vector<uint8_t> rgba;
  ASSERT_TRUE(toRgba(frame, w, h, rgba, why)) << why;
  auto px = [&](uint32_t x, uint32_t y) {
    const uint8_t* q = &rgba[(y * w + x) * 4];
    return std::vector<int>{q[0], q[1], q[2], q[3]};
  };
  EXPECT_EQ(px(0, 0), (std::vector<int>{90, 90, 90, 255}));
  EXPECT_EQ(px(1, 3), (std::vector<int>{90, 90, 90, 255}));
  EXPECT_EQ(px(3, 1), (std::vector<int>{254, 0, 0, 255}));
  EXPECT_EQ(px(2, 2), (std::vector<int>{0, 0, 254, 255}));
  // Odd sizes and missing planes are refused.
  EXPECT_FALSE(packFrame(mapped.planes(), kiosk::PixelFormat::kYuv420, 3, 4, stride, frame, why));
  EXPECT_NE(why.find("even size"), std::string::npos) << why;
  EXPECT_FALSE(
      packFrame({mapped.planes()[0]}, kiosk::PixelFormat::kYuv420, w, h, stride, frame, why));
  EXPECT_NE(why.find("1 planes, expected 3"), std::string::npos) << why;
  EXPECT_FALSE(packFrame(mapped.planes(), kiosk::PixelFormat::kYuyv, w, h, stride, frame, why));
}

TEST(CameraBuffers, UnmappableFdFailsCleanly) {
  EXPECT_THROW(MappedFrameBuffer({{-1, 0, 4096}}), HardwareUnavailable);
}

}  // namespace
}  // namespace penumbra::platform
