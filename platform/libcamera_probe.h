// libcamera 0.0.3 on the kiosk board (design.md §6): the camera manager and the list of
// cameras. Capture itself (configure XRGB8888, allocate buffers, requests completed on
// libcamera's thread) is not written yet; what exists is what the board program needs to
// decide at start-up whether libcamera has a camera or it must fall back.
#pragma once

#include <string>
#include <vector>

#include "platform/hardware.h"

namespace penumbra::platform {

// Starts a CameraManager and returns the ids of the cameras it lists (possibly none).
// Throws HardwareUnavailable when the manager itself cannot start.
std::vector<std::string> listLibcameraCameras();

// The first camera's id; throws HardwareUnavailable ("libcamera: no camera found ...") when
// there is none.
std::string requireLibcameraCamera();

}  // namespace penumbra::platform
