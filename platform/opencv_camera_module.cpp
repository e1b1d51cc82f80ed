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

// The module's factory, found once: dlopen's handle is kept for the life of the process (a
// camera object's code lives in the module, so it must never be unloaded while one may
// exist). Throws when no path gives a working module.
OpenCvCameraFactory findFactory() {
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
    if (void* symbol = dlsym(handle, kOpenCvCameraFactory)) {
      return reinterpret_cast<OpenCvCameraFactory>(symbol);
    }
    tried += "\n  " + path.string() + ": no " + kOpenCvCameraFactory;
    dlclose(handle);
  }
  throw HardwareUnavailable(std::string("camera: V4L2 needs ") + kOpenCvCameraModule +
                            " (OpenCV), which was not loaded:" + tried);
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
  // A function-local static: initialised once, under the language's own lock; a throw leaves
  // it uninitialised, so a later call tries again.
  static const OpenCvCameraFactory factory = findFactory();
  return std::unique_ptr<kiosk::FrameSource>(factory(device, width, height));
}

}  // namespace penumbra::platform
