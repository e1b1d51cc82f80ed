#include "apps/kiosk_check.h"

#include <sched.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <sstream>
#include <string>
#include <thread>

#include "kiosk/bundle_guard.h"
#include "kiosk/product_files.h"
#include "platform/hardware.h"
#include "platform/v4l2_devices.h"
#include "shadow/scene_bundle.h"
#ifdef PENUMBRA_HAVE_LIBCAMERA
#include "platform/libcamera_camera.h"
#endif

namespace penumbra::apps {
namespace {

std::string joined(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& i : items) s += (s.empty() ? "" : ", ") + i;
  return s;
}

// libcamera's camera ids, or why there are none.
std::vector<std::string> libcameraIds(std::string& why) {
#ifdef PENUMBRA_HAVE_LIBCAMERA
  try {
    return platform::listLibcameraCameras();
  } catch (const platform::HardwareUnavailable& e) {
    why = e.what();
  }
#else
  why = "this build has no libcamera (PENUMBRA_WITH_LIBCAMERA)";
#endif
  return {};
}

std::string describeV4l2(const std::filesystem::path& node) {
  for (const platform::V4l2Device& d : platform::listV4l2Devices()) {
    if (d.node == node) return node.string() + " (" + d.name + ")";
  }
  return node.string() + " (not present)";
}

const char* hudName(kiosk::HudMode m) {
  switch (m) {
    case kiosk::HudMode::kOff:
      return "off";
    case kiosk::HudMode::kService:
      return "service";
    case kiosk::HudMode::kOn:
      break;
  }
  return "on";
}

// The environment camera and live lighting's options, or the captured light without one.
void describeEnvironment(const kiosk::KioskConfig& c, std::ostream& out) {
  if (!c.environment) {
    out << "environment camera: none (the bundle's captured light)\n";
    return;
  }
  const kiosk::EnvironmentCameraSettings& e = *c.environment;
  std::string where;
  if (e.device.rfind("/dev/", 0) == 0) {
    where = describeV4l2(e.device);
  } else if (e.device.find('%') != std::string::npos) {
    where = e.device + " (image sequence)";
  } else {
    where = e.device + (std::filesystem::exists(e.device) ? " (recording)" : " (not present)");
  }
  std::ostringstream lens;
  if (!e.lensFile.empty()) lens << "lens file " << e.lensFile << ": ";
  lens << (e.equidistant180 ? "equidistant 180" : "fisheye") << " lens f " << e.lens.fx << " "
       << e.lens.fy << " centre " << e.lens.cx << " " << e.lens.cy;
  if (!e.equidistant180) {
    lens << " k " << e.lens.k[0] << " " << e.lens.k[1] << " " << e.lens.k[2] << " " << e.lens.k[3];
  }
  // How much of the hemisphere it sees (kiosk_config.cpp refuses less than 90°).
  lens << " reach " << std::round(e.lensReach * 180 / std::numbers::pi * 100) / 100 << " deg";
#ifdef PENUMBRA_HAVE_OPENCV_CAMERA
  const char* module = " (OpenCV module)";
#else
  const char* module = " (this build has no OpenCV: not opened)";
#endif
  out << "environment camera: " << where << module << " -> the bundle's captured light; " << e.width
      << "x" << e.height << ", " << lens.str() << ", response ";
  if (e.response) {
    out << "calibrated " << e.responseFile;
  } else if (e.gamma == 0) {
    out << "sRGB";
  } else {
    out << "gamma " << e.gamma;
  }
  out << ", exposure scale " << e.exposureScale;
  if (!e.bracketUs.empty()) {
    out << (e.bracketUs.size() >= 2 ? ", HDR from the exposure bracket " : ", exposure ");
    for (size_t i = 0; i < e.bracketUs.size(); ++i) out << (i ? "/" : "") << e.bracketUs[i];
    out << " us";
    if (e.device.rfind("/dev/", 0) == 0)
      out << " (" << e.settleFrames << " frames dropped after each change)";
  }
  out << "\n";
  const envmap::LiveLightsOptions& l = c.loop.liveLights;
  // The yaw back from the rotation: the image's +x goes to (cos, 0, sin).
  const double yaw = std::atan2(l.toWorld[0][2], l.toWorld[0][0]) * 180 / std::numbers::pi;
  out << "live lighting: " << l.samples << " samples, at most " << l.maxLights << " lights, yaw "
      << yaw << " deg, radiance scale " << l.radianceScale << ", stale after "
      << c.loop.environmentStaleAfterNs / 1'000'000 << " ms\n";
}

}  // namespace

int kioskThreads(const kiosk::KioskConfig& config) {
  if (config.threads > 0) return config.threads;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) {
    return std::min(CPU_COUNT(&set), 64);
  }
  return static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 64u));
}

void checkKioskConfig(const std::filesystem::path& configPath, std::ostream& out) {
  const kiosk::KioskConfig c = kiosk::loadKioskConfig(configPath);
  out << "config: " << configPath.string() << ": valid\n";
  shadow::SceneBundle bundle = shadow::loadBundle(c.bundle);
  std::vector<std::string> refused;
  const std::vector<uint32_t> usable = kiosk::validateProducts(bundle, refused);
  if (usable.empty()) {
    throw kiosk::ConfigError(c.bundle.string() + ": no usable product (" + joined(refused) + ")");
  }
  std::vector<std::string> names;
  names.reserve(usable.size());
  for (uint32_t i : usable) names.push_back(bundle.products[i].name);
  out << "bundle: " << c.bundle.string() << ": " << bundle.view.width << "x" << bundle.view.height
      << ", products " << joined(names) << "\n";
  for (const std::string& r : refused) out << "bundle: refused " << r << "\n";
  if (!c.lastGood.empty()) {
    out << "last good bundle: " << c.lastGood.string()
        << (std::filesystem::exists(c.lastGood)
                ? std::string(" (present)")
                : " (none yet: kept after " + std::to_string(kiosk::kFramesBeforeLastGood) +
                      " frames)")
        << "\n";
  }
  // The kiosk's own start-up swap (a file it would refuse is an error here).
  kiosk::KioskLog swaps;
  for (const kiosk::ProductFile& f : c.productFiles) {
    const std::string refusal = kiosk::swapProductFile(bundle, f, swaps, 0);
    if (!refusal.empty()) {
      throw kiosk::ConfigError(configPath.string() + ": product_files: " + refusal);
    }
    const auto swapped =
        std::find_if(bundle.products.begin(), bundle.products.end(),
                     [&](const shadow::ProductModel& p) { return p.name == f.product; });
    out << "product file: " << f.product << " <- " << f.file.string() << ": "
        << swapped->mesh.triangleCount() << " triangles\n";
  }

  // Camera, in the kiosk's fallback order.
  std::vector<std::string> steps;
  if (c.camera == "auto" || c.camera == "libcamera") {
    std::string why;
    const std::vector<std::string> ids = libcameraIds(why);
    if (!ids.empty()) {
      steps.push_back("libcamera " +
                      (c.cameraId.empty() ? ids.front() + " (the first)" : c.cameraId));
    } else {
      steps.push_back("libcamera: " + (why.empty() ? "no camera" : why));
    }
  }
  if (c.camera != "libcamera" && c.camera != "none") {
    steps.push_back("V4L2 " + describeV4l2(c.camera == "auto" ? "/dev/video0" : c.camera));
  }
  // "none" asks for the photograph itself, whatever camera_fallback says (openCamera).
  steps.push_back(c.cameraFallback == "simulated" && c.camera != "none"
                      ? "the simulated camera"
                      : "the calibration photograph");
  std::string order;
  for (const std::string& s : steps) order += (order.empty() ? "" : " -> ") + s;
  out << "camera: " << c.camera << ": " << order << "\n";
  out << "camera controls: exposure " << c.cameraControls.exposureUs << " us, analogue gain "
      << c.cameraControls.analogueGain << ", colour gains " << c.cameraControls.redGain << " "
      << c.cameraControls.blueGain << "; mirrored"
      << (c.loop.cameraOrientation.mirrorX ? " left-right" : "")
      << (c.loop.cameraOrientation.mirrorY ? " top-bottom" : "")
      << (c.loop.cameraOrientation.identity() ? " no" : "") << "\n";

  out << "gpio: " << c.gpioChip
      << (std::filesystem::exists(c.gpioChip) ? "" : " (not present: no buttons, no LED)")
      << "; lines";
  for (size_t b = 0; b < kiosk::kButtonCount; ++b) {
    out << " " << kiosk::buttonName(static_cast<kiosk::Button>(b)) << " " << c.buttonLines[b];
  }
  out << ", LED " << (c.ledLine < 0 ? std::string("none") : std::to_string(c.ledLine)) << "\n";

  const char* driver = std::getenv("SDL_VIDEODRIVER");
  out << "display: " << c.display;
  if (c.display == "sdl") {
    out << (c.fullscreen ? ", fullscreen" : ", windowed") << ", SDL_VIDEODRIVER "
        << (driver != nullptr ? std::string(driver) : "unset (SDL picks; kmsdrm on a board)");
  }
  if (c.display == "drm") {
    out << ", "
        << (c.drmDevice.empty()
                ? std::string("the first /dev/dri/card* with a connected screen")
                : c.drmDevice + (std::filesystem::exists(c.drmDevice) ? "" : " (not present)"));
  }
  out << "\n";
  describeEnvironment(c, out);
  out << "render: " << kioskThreads(c) << " threads" << (c.threads == 0 ? " (one per core)" : "")
      << "\n";
  out << "loop: " << 1'000'000'000 / c.loop.fastFrameNs << " fps, quality "
      << 1'000'000'000 / c.loop.qualityFrameNs << " fps, passes " << c.loop.minPasses << "-"
      << c.loop.maxPasses << ", HUD " << hudName(c.loop.hud);
  if (c.loop.hud == kiosk::HudMode::kService) {
    out << " (hold next + previous " << c.loop.serviceHoldNs / 1'000'000 << " ms)";
  }
  out << "\n";
}

void listCameras(std::ostream& out) {
  std::string why;
  const std::vector<std::string> ids = libcameraIds(why);
  out << "libcamera: " << ids.size() << " camera" << (ids.size() == 1 ? "" : "s")
      << (why.empty() ? "" : " (" + why + ")") << "\n";
  for (const std::string& id : ids) out << "  " << id << "\n";
  const std::vector<platform::V4l2Device> v4l2 = platform::listV4l2Devices();
  out << "V4L2: " << v4l2.size() << " device" << (v4l2.size() == 1 ? "" : "s") << "\n";
  for (const platform::V4l2Device& d : v4l2)
    out << "  " << d.node.string() << "  " << d.name << "\n";
}

}  // namespace penumbra::apps
