// The V4L2 listing of `penumbra-kiosk --list-cameras` on a sysfs tree laid out as the kernel
// lays out /sys/class/video4linux (this machine has no video device), and on the real one.
#include "platform/v4l2_devices.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/scratch_dir.h"

namespace penumbra::platform {
namespace {

TEST(V4l2Devices, ListsVideoNodesInNumberOrderWithTheirNames) {
  const std::filesystem::path sysfs = test::scratchPath("video4linux");
  std::filesystem::remove_all(sysfs);
  for (const char* node : {"video10", "video2", "video0", "vbi0", "v4l-subdev0", "videox"}) {
    std::filesystem::create_directories(sysfs / node);
  }
  std::ofstream(sysfs / "video0" / "name") << "vivid\n";
  std::ofstream(sysfs / "video2" / "name") << "UVC Camera (046d:0825)\n";
  const std::vector<V4l2Device> d = listV4l2Devices(sysfs);
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[0].node, "/dev/video0");
  EXPECT_EQ(d[0].name, "vivid");
  EXPECT_EQ(d[1].node, "/dev/video2");
  EXPECT_EQ(d[1].name, "UVC Camera (046d:0825)");
  EXPECT_EQ(d[2].node, "/dev/video10");
  EXPECT_EQ(d[2].name, "(no name)");  // no name file
  std::filesystem::remove_all(sysfs);
  EXPECT_TRUE(listV4l2Devices(sysfs).empty());  // no video4linux class: no device, no error
}

// The real sysfs: whatever this machine has, each entry is a /dev/videoN node.
TEST(V4l2Devices, RealSysfsListsOnlyVideoNodes) {
  for (const V4l2Device& d : listV4l2Devices()) {
    EXPECT_EQ(d.node.string().rfind("/dev/video", 0), 0u) << d.node;
    EXPECT_FALSE(d.name.empty());
  }
}

}  // namespace
}  // namespace penumbra::platform
