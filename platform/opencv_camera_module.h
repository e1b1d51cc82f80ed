// The V4L2 webcam backend (OpenCvCamera) lives in a module the kiosk loads only when it
// falls back to V4L2 (docs/kiosk.md, "Memory"). Linking OpenCV's videoio pulls in about 240
// shared libraries (GDAL, GDCM, HDF5, ...): 69.5 MB of resident memory before main() in a
// program that does nothing else (measured 2026-11-27, Debian 12 amd64), more than the whole
// kiosk's budget. A board that films with libcamera never maps them.
//
// The environment camera of live lighting (OpenCvEnvironmentCamera, an 8-bit fisheye read
// through the same VideoCapture) is in the same module, with a second factory: one set of
// OpenCV libraries mapped for either camera or both, one file to install and check (the
// package's check loads it), one loader. A sibling module would map the same libraries again
// for the ~0.3 MB of code that differs.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "kiosk/environment_camera.h"
#include "kiosk/frame_source.h"
#include "platform/opencv_environment_camera.h"

namespace penumbra::platform {

// The module's file name, and the one function it exports (C linkage, so dlsym finds it by
// this name). The function returns a new OpenCvCamera, or throws what its constructor throws.
inline constexpr const char* kOpenCvCameraModule = "libpenumbra_opencv_camera.so";
inline constexpr const char* kOpenCvCameraFactory = "penumbra_open_opencv_camera";
using OpenCvCameraFactory = kiosk::FrameSource* (*)(const std::string& device, uint32_t width,
                                                    uint32_t height);

// The environment camera's factory: a new OpenCvEnvironmentCamera, or what its constructor
// throws.
inline constexpr const char* kEnvironmentCameraFactory = "penumbra_open_environment_camera";
using EnvironmentCameraFactory =
    kiosk::EnvironmentCamera* (*)(const kiosk::EnvironmentCameraSettings& settings,
                                  const EnvironmentLog& log);

// Where the module is looked for, in order: beside the program (the build tree's bin/), then
// the install prefix's lib/penumbra/ (the program in <prefix>/bin/).
std::vector<std::filesystem::path> openCvCameraModulePaths(const std::filesystem::path& programDir);

// Loads the module (once per process; it stays loaded) and opens `device` with it; a device
// node that does not exist is refused before anything is loaded. Throws
// HardwareUnavailable when the module is missing or broken (naming the paths tried and the
// loader's reason) and whatever the camera's constructor throws.
std::unique_ptr<kiosk::FrameSource> openOpenCvCamera(const std::string& device, uint32_t width,
                                                     uint32_t height);

// Loads the module (as above) and opens the environment camera with it; a device node or a
// recording that does not exist is refused before anything is loaded (HardwareUnavailable).
// Throws HardwareUnavailable when the module is missing or broken or the source cannot be
// opened, envmap::FisheyeError for a lens that does not see the whole hemisphere.
std::unique_ptr<kiosk::EnvironmentCamera> openOpenCvEnvironmentCamera(
    const kiosk::EnvironmentCameraSettings& settings, const EnvironmentLog& log);

}  // namespace penumbra::platform
