// The real board's environment camera (issue 16; Havran et al. 2005 §5.1): an 8-bit fisheye
// camera looking at the zenith, read through OpenCV's VideoCapture — a V4L2 device
// ("/dev/videoN") or a recording (a video file, or an image sequence such as
// "frame_%03d.png"). Each frame is linearised by the configured response and exposure
// (environment_response.h: a 256-entry table), its saturated pixels counted and logged, and
// resampled into the hemisphere map through the lens (envmap::FisheyeResampler's fixed
// kernel). Lives in libpenumbra_opencv_camera.so beside the V4L2 room camera
// (opencv_camera_module.h): OpenCV's libraries are mapped only when a kiosk uses either.
//
// Pacing: a recording plays on the kiosk's clock — a video at its own frame rate (21 Hz when
// it does not say), an image sequence at 21 Hz, Havran's rate — and loops at its end; a device is
// read at most every 1.5 of its frame periods (and at most at 21 Hz), so that with a one-frame
// buffer the newest frame is normally waiting and the read does not wait for the sensor. A device
// that fails or goes is kDisconnected, said in the log with the reason, and reopened every second.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "kiosk/environment_camera.h"
#include "kiosk/status.h"

namespace penumbra::platform {

// Where the environment camera's messages go (the kiosk's log).
using EnvironmentLog = std::function<void(kiosk::LogLevel, const std::string&)>;

class OpenCvEnvironmentCamera final : public kiosk::EnvironmentCamera {
 public:
  // Throws HardwareUnavailable naming the device when it cannot be opened, FisheyeError when
  // the lens does not see the whole hemisphere, std::invalid_argument for a bad response.
  OpenCvEnvironmentCamera(const kiosk::EnvironmentCameraSettings& settings, EnvironmentLog log);
  ~OpenCvEnvironmentCamera() override;
  kiosk::GrabStatus grab(int64_t nowNs, envmap::HemisphereMap& map) override;
  std::string describe() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::platform
