// The V4L2 video devices the kernel has registered, for `penumbra-kiosk --list-cameras`:
// read from sysfs (/sys/class/video4linux/videoN/name), so listing opens no device and needs
// neither OpenCV nor permission to capture.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace penumbra::platform {

struct V4l2Device {
  std::filesystem::path node;  // /dev/videoN
  std::string name;            // the driver's card name ("vivid", "UVC Camera ...")
};

// In node order (video0, video1, ..., video10). `sysfs` is for tests.
std::vector<V4l2Device> listV4l2Devices(
    const std::filesystem::path& sysfs = "/sys/class/video4linux");

}  // namespace penumbra::platform
