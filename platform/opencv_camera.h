// A USB webcam through OpenCV's VideoCapture on V4L2 (design.md §2): the fallback camera
// when libcamera has none. Frames come as BGR8 and are checked and converted by the kiosk
// (kiosk::toRgba). A failed read is taken as the camera being gone; reopen() tries again.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "kiosk/frame_source.h"
#include "platform/hardware.h"

namespace penumbra::platform {

class OpenCvCamera final : public kiosk::FrameSource {
 public:
  // `device`: "/dev/videoN". Throws HardwareUnavailable naming the device when it cannot
  // be opened.
  OpenCvCamera(std::string device, uint32_t width, uint32_t height);
  ~OpenCvCamera() override;
  kiosk::GrabStatus grab(int64_t nowNs, kiosk::CameraFrame& out) override;
  bool reopen(int64_t nowNs) override;
  std::string describe() const override;

 private:
  bool open();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::platform
