// The environment camera of live lighting (issue 16 item 1; Havran et al. 2005 §5.1): a
// second camera with a fisheye lens looking at the zenith, whose HDR frames tell the kiosk
// where the room's light comes from now. A backend hands the kiosk each new frame already
// resampled into the hemisphere map the light sampler reads (envmap/hemisphere_map.h): the
// lens model and the HDR reconstruction belong to the camera; the kiosk turns the map into
// lights (envmap/live_lights.h) and the lights into the product's shading and shadows.
// firmware-sim/virtual_environment_camera.h plays fisheye EXR sequences.
#pragma once

#include <cstdint>
#include <string>

#include "envmap/hemisphere_map.h"
#include "kiosk/frame_source.h"

namespace penumbra::kiosk {

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
