// The kiosk camera through libcamera 0.0.3 (issue 6 §1; docs/kiosk.md "Camera"):
// CameraManager → Camera → acquire → a viewfinder configuration at the calibrated size in
// XRGB8888 (YUV420 when the pipeline offers no 32-bit RGB, RGB888 when it offers only
// 24-bit RGB, as vimc) → FrameBufferAllocator → buffers mapped
// once → one Request per buffer, each carrying the fixed controls (ExposureTime,
// AnalogueGain, ColourGains; AeEnable and AwbEnable off) → start.
//
// Threads: libcamera signals requestCompleted on its own thread. The handler packs the
// mapped planes into a CameraFrame, puts it in a FrameSlot (the newest frame wins), and
// requeues the request with the current controls; grab() on the kiosk's thread only takes
// from the slot and never blocks. The camera's `disconnected` signal closes the slot, so
// grab() reports kDisconnected and the kiosk calls reopen() now and then (hot-plug).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "kiosk/exposure_control.h"
#include "platform/hardware.h"

namespace penumbra::platform {

struct LibcameraOptions {
  std::string cameraId;  // empty: the first camera libcamera lists
  uint32_t width = 640, height = 480;
  kiosk::CameraControls controls;
  uint32_t buffers = 4;  // requests in flight
};

class LibcameraCamera final : public kiosk::ControllableCamera {
 public:
  // Throws HardwareUnavailable: the manager does not start, no camera is listed ("libcamera:
  // no camera found ..."), the named camera is not listed, it is busy, or it cannot deliver
  // the calibrated size in XRGB8888, YUV420 or RGB888 (sizes and formats named).
  explicit LibcameraCamera(LibcameraOptions options);
  ~LibcameraCamera() override;

  kiosk::GrabStatus grab(int64_t nowNs, kiosk::CameraFrame& out) override;
  bool reopen(int64_t nowNs) override;
  std::string describe() const override;
  void applyControls(const kiosk::CameraControls& controls) override;

  // Frames the kiosk never took (the slot held a newer one), and requests that failed.
  uint64_t framesOverwritten() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Starts a CameraManager and returns the ids of the cameras it lists (possibly none).
// Throws HardwareUnavailable when the manager itself cannot start.
std::vector<std::string> listLibcameraCameras();

}  // namespace penumbra::platform
