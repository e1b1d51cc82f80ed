// The real backends where the hardware is absent (issue 6; Debian kernels have no gpio-sim
// or vimc): each must fail with a clear HardwareUnavailable, never crash; the SDL display
// runs for real on SDL's offscreen driver.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "platform/hardware.h"
#ifdef PENUMBRA_HAVE_GPIOD
#include "platform/gpiod_io.h"
#endif
#ifdef PENUMBRA_HAVE_LIBCAMERA
#include "platform/libcamera_camera.h"
#endif
#ifdef PENUMBRA_HAVE_SDL2
#include "platform/sdl_display.h"
#endif
#ifdef PENUMBRA_HAVE_OPENCV_CAMERA
#include "platform/opencv_camera_module.h"
#endif

namespace penumbra::platform {
namespace {

#ifdef PENUMBRA_HAVE_GPIOD
TEST(GpiodBackend, MissingChipFailsCleanly) {
  GpioConfig c;
  c.chip = "/dev/gpiochip-penumbra-absent";
  try {
    GpiodButtons b(c);
    FAIL() << "opened a chip that does not exist";
  } catch (const HardwareUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/gpiochip-penumbra-absent"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(GpiodLed{c}, HardwareUnavailable);
}
#endif

#ifdef PENUMBRA_HAVE_LIBCAMERA
TEST(LibcameraBackend, ZeroCamerasFailsWithClearMessage) {
  // This machine has no camera: the real CameraManager starts and lists none, and opening
  // the kiosk camera says so (the board program then falls back, docs/kiosk.md).
  const std::vector<std::string> ids = listLibcameraCameras();
  if (!ids.empty()) GTEST_SKIP() << "a camera is attached: " << ids.front();
  try {
    LibcameraCamera camera(LibcameraOptions{});
    FAIL() << "opened a camera on a machine without one";
  } catch (const HardwareUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("libcamera: no camera found"), std::string::npos)
        << e.what();
  }
}

TEST(LibcameraBackend, BadControlsAreRefusedBeforeTheCameraIsTouched) {
  LibcameraOptions o;
  o.controls.exposureUs = 0;
  try {
    LibcameraCamera camera(o);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("exposure_us must be in [1, 10000000] (got 0)"),
              std::string::npos)
        << e.what();
  }
}
#endif

#ifdef PENUMBRA_HAVE_OPENCV_CAMERA
// A device node that does not exist is refused before the module is loaded.
TEST(OpenCvCameraBackend, MissingDeviceFailsCleanly) {
  try {
    const auto c = openOpenCvCamera("/dev/video-penumbra-absent", 640, 480);
    FAIL();
  } catch (const HardwareUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/video-penumbra-absent: no such device"),
              std::string::npos)
        << e.what();
  }
}

// A node that exists but is no camera goes through the module, as the kiosk opens a webcam:
// the module is found beside the test program (the build's bin/), and OpenCvCamera's own
// refusal, thrown inside the module, reaches the caller as HardwareUnavailable.
TEST(OpenCvCameraBackend, NodeThatIsNoCameraIsRefusedByTheModulesCamera) {
  try {
    const auto c = openOpenCvCamera("/dev/null", 640, 480);
    FAIL();
  } catch (const HardwareUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open /dev/null with V4L2"), std::string::npos)
        << e.what();
  }
}

TEST(OpenCvCameraBackend, ModuleIsLookedForBesideTheProgramThenInLibPenumbra) {
  const auto paths = openCvCameraModulePaths("/usr/bin");
  ASSERT_EQ(paths.size(), 2u);
  EXPECT_EQ(paths[0], std::filesystem::path("/usr/bin/libpenumbra_opencv_camera.so"));
  EXPECT_EQ(paths[1], std::filesystem::path("/usr/lib/penumbra/libpenumbra_opencv_camera.so"));
}
#endif

#ifdef PENUMBRA_HAVE_SDL2
TEST(SdlBackend, OffscreenShowsFrames) {
  setenv("SDL_VIDEODRIVER", "offscreen", 1);
  SdlDisplay d(64, 48, false);
  EXPECT_EQ(d.driver(), "offscreen");
  std::vector<uint8_t> frame(64 * 48 * 4, 128);
  EXPECT_TRUE(d.show(frame.data(), 64, 48));
  EXPECT_TRUE(d.show(frame.data(), 64, 48));
  EXPECT_EQ(d.framesShown(), 2u);
  EXPECT_THROW(d.show(frame.data(), 32, 48), std::invalid_argument);
}

TEST(SdlBackend, UnknownDriverFailsCleanly) {
  setenv("SDL_VIDEODRIVER", "penumbra-no-such-driver", 1);
  try {
    SdlDisplay d(64, 48, false);
    FAIL();
  } catch (const HardwareUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("SDL_VIDEODRIVER"), std::string::npos) << e.what();
  }
  unsetenv("SDL_VIDEODRIVER");
}
#endif

}  // namespace
}  // namespace penumbra::platform
