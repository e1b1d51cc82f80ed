// The exported entries of libpenumbra_opencv_camera.so (platform/opencv_camera_module.h).
#include "platform/opencv_camera.h"
#include "platform/opencv_camera_module.h"
#include "platform/opencv_environment_camera.h"

#include <type_traits>

extern "C" __attribute__((visibility("default"))) penumbra::kiosk::FrameSource*
penumbra_open_opencv_camera(const std::string& device, uint32_t width, uint32_t height) {
  return new penumbra::platform::OpenCvCamera(device, width, height);
}

extern "C" __attribute__((visibility("default"))) penumbra::kiosk::EnvironmentCamera*
penumbra_open_environment_camera(const penumbra::kiosk::EnvironmentCameraSettings& settings,
                                 const penumbra::platform::EnvironmentLog& log) {
  return new penumbra::platform::OpenCvEnvironmentCamera(settings, log);
}

// The types the loader casts the symbols to.
static_assert(std::is_same_v<decltype(&penumbra_open_opencv_camera),
                             penumbra::platform::OpenCvCameraFactory>);
static_assert(std::is_same_v<decltype(&penumbra_open_environment_camera),
                             penumbra::platform::EnvironmentCameraFactory>);
