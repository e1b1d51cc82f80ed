#include "platform/camera_buffers.h"

#include <sys/mman.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <map>

#include "platform/hardware.h"

namespace penumbra::platform {

MappedFrameBuffer::MappedFrameBuffer(const std::vector<PlaneRef>& planes) {
  // Each fd once, from 0 to the end of its last plane (offsets need not be page-aligned).
  std::map<int, uint64_t> extent;
  for (const PlaneRef& p : planes) extent[p.fd] = std::max(extent[p.fd], p.offset + p.length);
  std::map<int, const uint8_t*> base;
  for (const auto& [fd, length] : extent) {
    void* a = ::mmap(nullptr, length, PROT_READ, MAP_SHARED, fd, 0);
    if (a == MAP_FAILED) {
      const std::string err = std::strerror(errno);
      for (const Mapping& m : mappings_) ::munmap(m.address, m.length);  // no destructor runs
      throw HardwareUnavailable("camera: cannot map a frame buffer plane (fd " +
                                std::to_string(fd) + ", " + std::to_string(length) +
                                " bytes): " + err);
    }
    mappings_.push_back({a, length});
    base[fd] = static_cast<const uint8_t*>(a);
  }
  for (const PlaneRef& p : planes) planes_.emplace_back(base[p.fd] + p.offset, p.length);
}

MappedFrameBuffer::~MappedFrameBuffer() {
  for (const Mapping& m : mappings_) ::munmap(m.address, m.length);
}

MappedFrameBuffer::MappedFrameBuffer(MappedFrameBuffer&& other) noexcept
    : mappings_(std::move(other.mappings_)), planes_(std::move(other.planes_)) {
  other.mappings_.clear();
  other.planes_.clear();
}

bool packFrame(const std::vector<std::span<const uint8_t>>& planes, kiosk::PixelFormat format,
               uint32_t width, uint32_t height, uint32_t stride, kiosk::CameraFrame& out,
               std::string& why) {
  std::vector<size_t> need;
  if (format == kiosk::PixelFormat::kXrgb8888 || format == kiosk::PixelFormat::kBgr8) {
    const uint32_t bpp = format == kiosk::PixelFormat::kXrgb8888 ? 4 : 3;
    if (stride < width * bpp) {
      why = std::string(kiosk::pixelFormatName(format)) + " stride " + std::to_string(stride) +
            " < " + std::to_string(bpp) + " x width " + std::to_string(width);
      return false;
    }
    need = {size_t{stride} * height};
  } else if (format == kiosk::PixelFormat::kYuv420) {
    if (width % 2 || height % 2 || stride < width) {
      why = "YUV420 needs an even size and stride >= width (got " + std::to_string(width) + "x" +
            std::to_string(height) + ", stride " + std::to_string(stride) + ")";
      return false;
    }
    const size_t chroma = size_t{stride / 2} * (height / 2);
    need = {size_t{stride} * height, chroma, chroma};
  } else {
    why = std::string("cannot pack ") + kiosk::pixelFormatName(format) + " frames";
    return false;
  }
  if (planes.size() != need.size()) {
    why = std::string(kiosk::pixelFormatName(format)) + ": " + std::to_string(planes.size()) +
          " planes, expected " + std::to_string(need.size());
    return false;
  }
  size_t total = 0;
  for (size_t i = 0; i < need.size(); ++i) {
    if (planes[i].size() < need[i]) {
      why = std::string(kiosk::pixelFormatName(format)) + " plane " + std::to_string(i) + ": " +
            std::to_string(planes[i].size()) + " bytes, " + std::to_string(need[i]) + " needed";
      return false;
    }
    total += need[i];
  }
  out.width = width;
  out.height = height;
  out.stride = stride;
  out.format = format;
  out.data.resize(total);
  uint8_t* dst = out.data.data();
  for (size_t i = 0; i < need.size(); ++i) dst = std::copy_n(planes[i].data(), need[i], dst);
  return true;
}

}  // namespace penumbra::platform
