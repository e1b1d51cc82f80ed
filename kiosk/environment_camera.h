// The environment camera of live lighting (issue 16 item 1; Havran et al. 2005 §5.1): a
// second camera with a fisheye lens looking at the zenith, whose HDR frames tell the kiosk
// where the room's light comes from now. A backend hands the kiosk each new frame already
// resampled into the hemisphere map the light sampler reads (envmap/hemisphere_map.h): the
// lens model and the HDR reconstruction belong to the camera; the kiosk turns the map into
// lights (envmap/live_lights.h) and the lights into the product's shading and shadows.
// firmware-sim/virtual_environment_camera.h plays fisheye EXR sequences;
// platform/opencv_environment_camera.h reads the real board's 8-bit fisheye camera.
#pragma once

#include <cstdint>
#include <string>

#include "envmap/fisheye_resampler.h"
#include "envmap/hemisphere_map.h"
#include "kiosk/frame_source.h"

namespace penumbra::kiosk {

// The real board's environment camera as the configuration gives it (kiosk_config.h,
// "environment"; the backend is platform/opencv_environment_camera.h): an 8-bit fisheye
// video — a V4L2 device or a video file — linearised by a response and an exposure, then
// resampled into the hemisphere map through the lens.
struct EnvironmentCameraSettings {
  std::string device;              // "/dev/videoN", or a video file / image sequence path
  uint32_t width = 0, height = 0;  // the frames' size (asked of a device; the lens's)
  envmap::FisheyeLens lens;        // cv::fisheye intrinsics for width × height frames
  bool equidistant180 = true;      // the lens was given as "equidistant180" (for --check)
  // The frames' response: 0 for sRGB (IEC 61966-2-1), otherwise a gamma, value^gamma.
  double gamma = 0;
  // Linear values are divided by this (the exposure the room's radiance scale was set with).
  double exposureScale = 1;
};

class EnvironmentCamera {
 public:
  virtual ~EnvironmentCamera() = default;
  // kFrame with the newest frame captured at or before `nowNs` in `map` when it is newer
  // than the last one returned; kNoFrame otherwise; kDisconnected when the camera is gone.
  // Throws core::Error naming the frame when it cannot be used (wrong size, bad values).
  virtual GrabStatus grab(int64_t nowNs, envmap::HemisphereMap& map) = 0;
  virtual std::string describe() const = 0;
};

}  // namespace penumbra::kiosk
