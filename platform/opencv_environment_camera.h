// The real board's environment camera (issue 16; Havran et al. 2005 §5.1): an 8-bit fisheye
// camera looking at the zenith, read through OpenCV's VideoCapture — a V4L2 device
// ("/dev/videoN") or a recording (a video file, or an image sequence such as
// "frame_%03d.png"). Each frame is linearised by the configured response — sRGB, a gamma, or
// the camera's own calibrated by `penumbra camera-response` (environment_response.h: a
// 256-entry table per channel) — and exposure, and resampled into the hemisphere map through
// the lens (envmap::FisheyeResampler's fixed kernel). Lives in libpenumbra_opencv_camera.so
// beside the V4L2 room camera (opencv_camera_module.h): OpenCV's libraries are mapped only
// when a kiosk uses either.
//
// HDR (Debevec & Malik 1997): with "bracket_us" of n ≥ 2 times the camera cycles through
// them frame by frame — a device is set to manual exposure and to each time in turn, and the
// first settle_frames frames after each change are dropped (a V4L2 sensor applies a new
// exposure a frame or two late); frame i of a recording was shot with bracket_us[i % n] — and
// every new frame is merged with the newest frame of each other time (bracket_merge.h), from
// the n-th frame on. Pixels clipped even in the shortest exposure are counted and logged (at
// most every 10 s). A light that moves between the exposures of one window ghosts: it is
// merged from where each exposure saw it. Without a bracket (or with one time), a single
// 8-bit frame: a lamp that saturates it (a channel ≥ 250) under-reports its power, and is
// said.
//
// Pacing: a recording plays on the kiosk's clock — a video at its own frame rate (21 Hz when
// it does not say), an image sequence at 21 Hz, Havran's rate — and loops at its end; a device is
// read at most every 1.5 of its frame periods (and at most at 21 Hz), so that with a one-frame
// buffer the newest frame is normally waiting and the read does not wait for the sensor; with a
// bracket each read is one frame of the cycle (dropped ones included), so a device's merged map
// changes at most every (settle_frames + 1) reads. A device that fails or goes, or refuses a
// manual exposure, is kDisconnected, said in the log with the reason, and reopened every second.
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
  // Throws HardwareUnavailable naming the device when it cannot be opened (or, with a
  // bracket, takes no manual exposure), FisheyeError when the lens does not see the whole
  // hemisphere, std::invalid_argument for a bad gamma, exposure or bracket. A calibrated
  // response is taken as kiosk_config read it (readCameraResponse checked it).
  OpenCvEnvironmentCamera(const kiosk::EnvironmentCameraSettings& settings, EnvironmentLog log);
  ~OpenCvEnvironmentCamera() override;
  kiosk::GrabStatus grab(int64_t nowNs, envmap::HemisphereMap& map) override;
  std::string describe() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::platform
