#include "platform/opencv_camera_module.h"

#include <dlfcn.h>

#include <system_error>

#include "platform/hardware.h"

namespace penumbra::platform {
namespace {

std::filesystem::path programDir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path() : exe.parent_path();
}

// The module's handle, found once and kept for the life of the process (a camera object's
// code lives in the module, so it must never be unloaded while one may exist). Throws when no
// path gives a module that exports both factories.
void* loadModule() {
  std::string tried;
  for (const std::filesystem::path& path : openCvCameraModulePaths(programDir())) {
    if (!std::filesystem::exists(path)) {
      tried += "\n  " + path.string() + ": not there";
      continue;
    }
    // RTLD_LOCAL: OpenCV's symbols stay the module's own.
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* why = dlerror();
      tried += "\n  " + path.string() + ": " + (why != nullptr ? why : "cannot be loaded");
      continue;
    }
    if (dlsym(handle, kOpenCvCameraFactory) != nullptr &&
        dlsym(handle, kEnvironmentCameraFactory) != nullptr) {
      return handle;
    }
    tried += "\n  " + path.string() + ": no " + kOpenCvCameraFactory + " or " +
             kEnvironmentCameraFactory;
    dlclose(handle);
  }
  throw HardwareUnavailable(std::string("V4L2 and video files need ") + kOpenCvCameraModule +
                            " (OpenCV), which was not loaded:" + tried);
}

// `name` from the module; a module that cannot be loaded is HardwareUnavailable, its message
// after `who` ("camera: ").
void* moduleSymbol(const char* name, const std::string& who) {
  try {
    // A function-local static: initialised once, under the language's own lock; a throw
    // leaves it uninitialised, so a later call tries again.
    static void* const handle = loadModule();
    return dlsym(handle, name);
  } catch (const HardwareUnavailable& e) {
    throw HardwareUnavailable(who + e.what());
  }
}

}  // namespace

std::vector<std::filesystem::path> openCvCameraModulePaths(const std::filesystem::path& dir) {
  return {dir / kOpenCvCameraModule, dir.parent_path() / "lib" / "penumbra" / kOpenCvCameraModule};
}

std::unique_ptr<kiosk::FrameSource> openOpenCvCamera(const std::string& device, uint32_t width,
                                                     uint32_t height) {
  // No device, no module: OpenCV's libraries are not worth loading to say so (the camera's
  // constructor words it the same way).
  if (!std::filesystem::exists(device)) {
    throw HardwareUnavailable("camera: cannot open " + device + ": no such device");
  }
  const auto factory =
      reinterpret_cast<OpenCvCameraFactory>(moduleSymbol(kOpenCvCameraFactory, "camera: "));
  return std::unique_ptr<kiosk::FrameSource>(factory(device, width, height));
}

std::unique_ptr<kiosk::EnvironmentCamera> openOpenCvEnvironmentCamera(
    const kiosk::EnvironmentCameraSettings& settings, const EnvironmentLog& log) {
  // As above: a source that is not there is said without loading OpenCV. An image sequence
  // ("frame_%03d.png") is left to VideoCapture.
  if (settings.device.find('%') == std::string::npos && !std::filesystem::exists(settings.device)) {
    throw HardwareUnavailable("environment camera: cannot open " + settings.device + ": no such " +
                              (settings.device.rfind("/dev/", 0) == 0 ? "device" : "file"));
  }
  const auto factory = reinterpret_cast<EnvironmentCameraFactory>(
      moduleSymbol(kEnvironmentCameraFactory, "environment camera: "));
  return std::unique_ptr<kiosk::EnvironmentCamera>(factory(settings, log));
}

}  // namespace penumbra::platform
