#include "platform/libcamera_probe.h"

#include <libcamera/camera.h>
#include <libcamera/camera_manager.h>

#include <memory>

namespace penumbra::platform {

std::vector<std::string> listLibcameraCameras() {
  auto manager = std::make_unique<libcamera::CameraManager>();
  const int rc = manager->start();
  if (rc != 0) {
    throw HardwareUnavailable("libcamera: the camera manager did not start (error " +
                              std::to_string(rc) + ")");
  }
  std::vector<std::string> ids;
  for (const std::shared_ptr<libcamera::Camera>& c : manager->cameras()) ids.push_back(c->id());
  manager->stop();
  return ids;
}

std::string requireLibcameraCamera() {
  const std::vector<std::string> ids = listLibcameraCameras();
  if (ids.empty()) {
    throw HardwareUnavailable(
        "libcamera: no camera found (is the ribbon cable seated, camera_auto_detect=1 in "
        "config.txt?); falling back to a USB webcam or the calibration photograph");
  }
  return ids.front();
}

}  // namespace penumbra::platform
