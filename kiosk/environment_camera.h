// The environment camera of live lighting (issue 16 item 1; Havran et al. 2005 §5.1): a
// second camera with a fisheye lens looking at the zenith, whose HDR frames tell the kiosk
// where the room's light comes from now. A backend hands the kiosk each new frame already
// resampled into the hemisphere map the light sampler reads (envmap/hemisphere_map.h): the
// lens model and the HDR reconstruction belong to the camera; the kiosk turns the map into
// lights (envmap/live_lights.h) and the lights into the product's shading and shadows.
// firmware-sim/virtual_environment_camera.h plays fisheye EXR sequences;
// platform/opencv_environment_camera.h reads the real board's 8-bit fisheye camera, HDR by
// exposure bracketing through its calibrated response.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "envmap/fisheye_resampler.h"
#include "envmap/hemisphere_map.h"
#include "kiosk/camera_response_file.h"
#include "kiosk/frame_source.h"

namespace penumbra::kiosk {

// The real board's environment camera as the configuration gives it (kiosk_config.h,
// "environment"; the backend is platform/opencv_environment_camera.h): an 8-bit fisheye
// video — a V4L2 device or a recording — linearised by a response (sRGB, a gamma, or the
// camera's own, calibrated from a bracket: camera_response_file.h) and an exposure, merged
// into HDR from a cycle of exposure times when a bracket is given (Debevec & Malik 1997),
// then resampled into the hemisphere map through the lens.
struct EnvironmentCameraSettings {
  std::string device;              // "/dev/videoN", or a video file / image sequence path
  uint32_t width = 0, height = 0;  // the frames' size (asked of a device; the lens's)
  envmap::FisheyeLens lens;        // cv::fisheye intrinsics for width × height frames
  bool equidistant180 = true;      // the lens was given as "equidistant180" (for --check)
  std::string lensFile;            // the lens file it was read from (`penumbra calibrate-fisheye`)
  double lensReach = 0;            // envmap::nearestEdgeReach(lens), radians (≥ π/2)
  // The frames' response: 0 for sRGB (IEC 61966-2-1), otherwise a gamma, value^gamma —
  // unless `response` holds the camera's calibrated curves (read from `responseFile`).
  double gamma = 0;
  std::optional<CameraResponseCurves> response;
  std::string responseFile;
  // Linear values are divided by this (the exposure the room's radiance scale was set with).
  double exposureScale = 1;
  // Exposure times, increasing, cycled frame by frame (empty: the camera's own exposure, one
  // frame at a time). A device is set to each in turn; frame i of a recording was shot with
  // bracketUs[i % n]. With n ≥ 2 every new frame is merged with the newest of each other time.
  std::vector<int64_t> bracketUs;
  // A device only: frames dropped after each change of exposure (a V4L2 sensor applies a new
  // exposure a frame or two late).
  uint32_t settleFrames = 2;
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
