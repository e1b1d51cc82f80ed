#include "kiosk/frame_source.h"

#include <cstddef>

namespace penumbra::kiosk {

const char* pixelFormatName(PixelFormat format) {
  switch (format) {
    case PixelFormat::kRgba8:
      return "RGBA8";
    case PixelFormat::kXrgb8888:
      return "XRGB8888";
    case PixelFormat::kBgr8:
      return "BGR8";
    case PixelFormat::kYuyv:
      return "YUYV";
    case PixelFormat::kYuv420:
      return "YUV420";
  }
  return "unknown";
}

namespace {

uint32_t bytesPerPixel(PixelFormat format) {
  switch (format) {
    case PixelFormat::kRgba8:
    case PixelFormat::kXrgb8888:
      return 4;
    case PixelFormat::kBgr8:
      return 3;
    case PixelFormat::kYuyv:
      return 2;
    case PixelFormat::kYuv420:
      return 1;  // the luma plane; chroma follows at a quarter of the size each
  }
  return 0;
}

uint8_t clampToByte(int32_t v) {
  return static_cast<uint8_t>(v < 0 ? 0 : v > 255 ? 255 : v);
}

// Where source row `y` goes in the output, and which way along it: the mounting's mirrors,
// decided once a row.
struct OutputRow {
  uint8_t* first;  // the pixel source column 0 lands on
  ptrdiff_t step;  // +4, or -4 when mirrored left-right
};
OutputRow outputRow(std::vector<uint8_t>& rgba, uint32_t width, uint32_t height, uint32_t y,
                    FrameOrientation o) {
  uint8_t* row = rgba.data() + size_t{o.mirrorY ? height - 1 - y : y} * width * 4;
  return o.mirrorX ? OutputRow{row + size_t{width - 1} * 4, -4} : OutputRow{row, 4};
}

// Full-range BT.601 (JFIF): R = Y + 1.402 V', G = Y - 0.344136 U' - 0.714136 V',
// B = Y + 1.772 U' with U' = U - 128, V' = V - 128; coefficients × 65536, rounded to nearest
// (>> of a negative value is an arithmetic shift in C++20, i.e. floor).
void yuv420ToRgba(const CameraFrame& f, std::vector<uint8_t>& rgba, FrameOrientation o) {
  const uint32_t cstride = f.stride / 2;
  const uint8_t* yPlane = f.data.data();
  const uint8_t* uPlane = yPlane + size_t{f.stride} * f.height;
  const uint8_t* vPlane = uPlane + size_t{cstride} * (f.height / 2);
  for (uint32_t y = 0; y < f.height; ++y) {
    const OutputRow out = outputRow(rgba, f.width, f.height, y, o);
    uint8_t* dst = out.first;
    for (uint32_t x = 0; x < f.width; ++x, dst += out.step) {
      const int32_t luma = yPlane[size_t{y} * f.stride + x];
      const size_t c = size_t{y / 2} * cstride + x / 2;
      const int32_t u = uPlane[c] - 128, v = vPlane[c] - 128;
      dst[0] = clampToByte(luma + ((91881 * v + 32768) >> 16));
      dst[1] = clampToByte(luma - ((22554 * u + 46802 * v + 32768) >> 16));
      dst[2] = clampToByte(luma + ((116130 * u + 32768) >> 16));
      dst[3] = 255;
    }
  }
}

}  // namespace

bool toRgba(const CameraFrame& frame, uint32_t width, uint32_t height, std::vector<uint8_t>& rgba,
            std::string& why, FrameOrientation orientation) {
  const std::string got = std::to_string(frame.width) + "x" + std::to_string(frame.height) + " " +
                          pixelFormatName(frame.format);
  if (frame.width != width || frame.height != height) {
    why = "frame size " + got + ", the calibrated view is " + std::to_string(width) + "x" +
          std::to_string(height);
    return false;
  }
  const uint32_t bpp = bytesPerPixel(frame.format);
  if (frame.format == PixelFormat::kYuyv || bpp == 0) {
    why = "frame format " + got + " is not supported (configure RGBA8, XRGB8888, YUV420 or BGR8)";
    return false;
  }
  const size_t chromaBytes =
      frame.format == PixelFormat::kYuv420 ? 2 * size_t{frame.stride / 2} * (height / 2) : 0;
  if (frame.stride < width * bpp ||
      frame.data.size() < static_cast<size_t>(frame.stride) * height + chromaBytes ||
      (frame.format == PixelFormat::kYuv420 && (width % 2 || height % 2))) {
    why = "frame buffer of " + std::to_string(frame.data.size()) + " bytes, stride " +
          std::to_string(frame.stride) + ", too short for " + got;
    return false;
  }
  rgba.resize(static_cast<size_t>(width) * height * 4);
  if (frame.format == PixelFormat::kYuv420) {
    yuv420ToRgba(frame, rgba, orientation);
    return true;
  }
  for (uint32_t y = 0; y < height; ++y) {
    const uint8_t* src = frame.data.data() + static_cast<size_t>(y) * frame.stride;
    const OutputRow out = outputRow(rgba, width, height, y, orientation);
    uint8_t* dst = out.first;
    for (uint32_t x = 0; x < width; ++x, src += bpp, dst += out.step) {
      switch (frame.format) {
        case PixelFormat::kRgba8:
          dst[0] = src[0], dst[1] = src[1], dst[2] = src[2];
          break;
        case PixelFormat::kXrgb8888:
        case PixelFormat::kBgr8:
          dst[0] = src[2], dst[1] = src[1], dst[2] = src[0];
          break;
        case PixelFormat::kYuyv:
        case PixelFormat::kYuv420:
          break;
      }
      dst[3] = 255;  // the compositor's background is opaque
    }
  }
  return true;
}

}  // namespace penumbra::kiosk
