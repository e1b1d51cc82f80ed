#include "platform/frame_source.h"

namespace penumbra::platform {

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
  }
  return 0;
}

}  // namespace

bool toRgba(const CameraFrame& frame, uint32_t width, uint32_t height, std::vector<uint8_t>& rgba,
            std::string& why) {
  const std::string got = std::to_string(frame.width) + "x" + std::to_string(frame.height) + " " +
                          pixelFormatName(frame.format);
  if (frame.width != width || frame.height != height) {
    why = "frame size " + got + ", the calibrated view is " + std::to_string(width) + "x" +
          std::to_string(height);
    return false;
  }
  const uint32_t bpp = bytesPerPixel(frame.format);
  if (frame.format == PixelFormat::kYuyv || bpp == 0) {
    why = "frame format " + got + " is not supported (configure RGBA8, XRGB8888 or BGR8)";
    return false;
  }
  if (frame.stride < width * bpp ||
      frame.data.size() < static_cast<size_t>(frame.stride) * height) {
    why = "frame buffer of " + std::to_string(frame.data.size()) + " bytes, stride " +
          std::to_string(frame.stride) + ", too short for " + got;
    return false;
  }
  rgba.resize(static_cast<size_t>(width) * height * 4);
  for (uint32_t y = 0; y < height; ++y) {
    const uint8_t* src = frame.data.data() + static_cast<size_t>(y) * frame.stride;
    uint8_t* dst = rgba.data() + static_cast<size_t>(y) * width * 4;
    for (uint32_t x = 0; x < width; ++x, src += bpp, dst += 4) {
      switch (frame.format) {
        case PixelFormat::kRgba8:
          dst[0] = src[0], dst[1] = src[1], dst[2] = src[2];
          break;
        case PixelFormat::kXrgb8888:
        case PixelFormat::kBgr8:
          dst[0] = src[2], dst[1] = src[1], dst[2] = src[0];
          break;
        case PixelFormat::kYuyv:
          break;
      }
      dst[3] = 255;  // the compositor's background is opaque
    }
  }
  return true;
}

}  // namespace penumbra::platform
