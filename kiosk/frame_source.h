// The camera behind a small interface (design.md §2): the kiosk asks for the newest frame
// each display frame; libcamera, OpenCV (V4L2) and the simulated camera of firmware-sim/
// implement it. Frames are converted to the RGBA8 background of the compositor here, once,
// with every size and format check in one place, so a backend cannot hand the renderer a
// frame it would misread.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace penumbra::kiosk {

// Pixel layouts the backends deliver. Bytes in memory order.
enum class PixelFormat : uint32_t {
  kRgba8,     // R, G, B, A
  kXrgb8888,  // libcamera/DRM XRGB8888 on a little-endian CPU: B, G, R, X
  kBgr8,      // OpenCV's default Mat layout, libcamera RGB888: B, G, R
  kYuyv,      // packed 4:2:2 (not converted: the kiosk configures XRGB8888)
  kYuv420,    // libcamera YUV420 (YU12): Y plane (stride), then U and V (stride / 2), JPEG range
};

const char* pixelFormatName(PixelFormat format);

struct CameraFrame {
  uint32_t width = 0, height = 0;
  uint32_t stride = 0;  // bytes per row (>= width * bytes per pixel)
  PixelFormat format = PixelFormat::kRgba8;
  uint64_t sequence = 0;      // increases by one per captured frame (gaps = drops)
  int64_t captureNs = 0;      // sensor timestamp on the kiosk's clock
  int32_t exposureUs = 0;     // exposure the sensor applied (libcamera metadata); 0: unknown
  std::vector<uint8_t> data;  // stride * height bytes
};

enum class GrabStatus {
  kFrame,         // `out` holds a frame newer than any returned before
  kNoFrame,       // nothing new yet (late or dropped frame): keep showing the last one
  kDisconnected,  // the camera is gone; call reopen() now and then
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // Never blocks longer than one camera period. `nowNs` is the kiosk clock (the simulated
  // camera needs it; real backends use it only for logging).
  virtual GrabStatus grab(int64_t nowNs, CameraFrame& out) = 0;
  // Tries to get a disconnected camera back; true when frames may flow again.
  virtual bool reopen(int64_t nowNs) = 0;
  virtual std::string describe() const = 0;
};

// How the camera is mounted: a sensor upside down is mirrored on both axes (rotated by 180°);
// a camera filming through a mirror, on one. Quarter turns are not offered: the calibrated
// view has one size, which a quarter turn would swap.
struct FrameOrientation {
  bool mirrorX = false, mirrorY = false;
  bool identity() const { return !mirrorX && !mirrorY; }
};

// Converts `frame` into RGBA8 (alpha 255) of exactly width × height, mirrored as `orientation`
// says (the conversion writes each pixel where the mounting puts it: no second pass). Returns
// false and sets `why` (e.g. "640x480 XRGB8888 expected, got 320x240 XRGB8888") for a frame of
// another size, an unsupported format, or a buffer shorter than stride × height; `rgba` is
// then untouched. YUV420 is converted with the full-range BT.601 matrix of JPEG/sYCC (what
// libcamera's viewfinder stream reports) in 16-bit fixed point, integers only.
bool toRgba(const CameraFrame& frame, uint32_t width, uint32_t height, std::vector<uint8_t>& rgba,
            std::string& why, FrameOrientation orientation = {});

}  // namespace penumbra::kiosk
