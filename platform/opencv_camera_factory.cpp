// The exported entry of libpenumbra_opencv_camera.so (platform/opencv_camera_module.h).
#include "platform/opencv_camera.h"
#include "platform/opencv_camera_module.h"

#include <type_traits>

extern "C" __attribute__((visibility("default"))) penumbra::kiosk::FrameSource*
penumbra_open_opencv_camera(const std::string& device, uint32_t width, uint32_t height) {
  return new penumbra::platform::OpenCvCamera(device, width, height);
}

// The type the loader casts the symbol to.
static_assert(std::is_same_v<decltype(&penumbra_open_opencv_camera),
                             penumbra::platform::OpenCvCameraFactory>);
