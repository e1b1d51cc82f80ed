// Camera frame buffers as the kernel hands them over (issue 6 §1): dma-buf planes that a
// capture backend maps read-only, then packs into one CameraFrame for the kiosk. Kept apart
// from the libcamera backend so the mapping and packing run (and are tested) without a
// camera: a memfd stands in for the dma-buf, the code path is the same mmap.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "kiosk/frame_source.h"

namespace penumbra::platform {

// One plane of a frame buffer: `length` bytes at `offset` in the file `fd`. The planes of a
// multi-planar buffer often share one fd at increasing offsets (libcamera does this for
// YUV420); each distinct fd is mapped once.
struct PlaneRef {
  int fd = -1;
  uint64_t offset = 0;
  uint64_t length = 0;
};

class MappedFrameBuffer {
 public:
  // Maps every plane read-only. Throws HardwareUnavailable naming the plane and errno's text
  // when a mapping fails.
  explicit MappedFrameBuffer(const std::vector<PlaneRef>& planes);
  ~MappedFrameBuffer();
  MappedFrameBuffer(MappedFrameBuffer&& other) noexcept;
  MappedFrameBuffer& operator=(MappedFrameBuffer&&) = delete;
  MappedFrameBuffer(const MappedFrameBuffer&) = delete;
  MappedFrameBuffer& operator=(const MappedFrameBuffer&) = delete;

  const std::vector<std::span<const uint8_t>>& planes() const { return planes_; }

 private:
  struct Mapping {
    void* address;
    size_t length;
  };
  std::vector<Mapping> mappings_;
  std::vector<std::span<const uint8_t>> planes_;
};

// Packs the planes of one captured frame into `out` (data, width, height, stride, format).
// kXrgb8888 and kBgr8 (libcamera RGB888): one plane of stride × height bytes. kYuv420: three planes
// Y (stride × height), U and V (stride/2 × height/2 each); width and height even. Returns false and
// sets `why` for a format it does not pack, the wrong plane count or a plane too short.
// `out.sequence` and the timestamps are the caller's.
bool packFrame(const std::vector<std::span<const uint8_t>>& planes, kiosk::PixelFormat format,
               uint32_t width, uint32_t height, uint32_t stride, kiosk::CameraFrame& out,
               std::string& why);

}  // namespace penumbra::platform
