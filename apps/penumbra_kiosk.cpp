// `penumbra-kiosk CONFIG.json`: the board program (issue 6, docs/kiosk.md). The kiosk loop
// of platform/ with the real peripherals, each falling back when absent: camera libcamera
// (probe only; capture not written yet) → V4L2 webcam (OpenCV) → the calibration photograph;
// buttons and LED on libgpiod → none (attract mode only); screen SDL2 → none (frames are
// rendered and counted, for a headless check). Every fallback is logged to stderr (journald).
#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "apps/render_flags.h"
#include "platform/bundle_guard.h"
#include "platform/hardware.h"
#include "platform/kiosk_loop.h"
#ifdef PENUMBRA_HAVE_GPIOD
#include "platform/gpiod_io.h"
#endif
#ifdef PENUMBRA_HAVE_LIBCAMERA
#include "platform/libcamera_probe.h"
#endif
#ifdef PENUMBRA_HAVE_OPENCV_CAMERA
#include "platform/opencv_camera.h"
#endif
#ifdef PENUMBRA_HAVE_SDL2
#include "platform/sdl_display.h"
#endif

using namespace penumbra;
using nlohmann::json;

namespace {

struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Config {
  std::filesystem::path bundle, lastGood;
  std::string camera = "auto";  // auto | libcamera | /dev/videoN | none
  std::string gpioChip = "/dev/gpiochip0";
  std::string display = "sdl";  // sdl | none
  bool fullscreen = true;
};

Config loadConfig(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path.string() + ": cannot open");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    throw ConfigError(path.string() + ": not valid JSON (" + e.what() + ")");
  }
  if (!j.is_object()) throw ConfigError(path.string() + ": must be an object");
  const std::set<std::string> known{"bundle",  "last_good_bundle", "camera",  "gpio_chip",
                                    "display", "fullscreen",       "_comment"};
  for (const auto& [k, v] : j.items()) {
    if (!known.count(k)) throw ConfigError(path.string() + ": " + k + ": unknown key");
  }
  auto str = [&](const char* key, std::string& out) {
    if (!j.contains(key)) return;
    if (!j[key].is_string()) throw ConfigError(path.string() + ": " + key + ": must be a string");
    out = j[key].get<std::string>();
  };
  Config c;
  std::string bundle, lastGood;
  str("bundle", bundle);
  if (bundle.empty()) throw ConfigError(path.string() + ": bundle: required");
  str("last_good_bundle", lastGood);
  str("camera", c.camera);
  str("gpio_chip", c.gpioChip);
  str("display", c.display);
  if (c.display != "sdl" && c.display != "none") {
    throw ConfigError(path.string() + ": display: 'sdl' or 'none', not '" + c.display + "'");
  }
  if (j.contains("fullscreen")) {
    if (!j["fullscreen"].is_boolean()) {
      throw ConfigError(path.string() + ": fullscreen: must be true or false");
    }
    c.fullscreen = j["fullscreen"].get<bool>();
  }
  const std::filesystem::path dir = path.parent_path();
  c.bundle = dir / bundle;
  if (!lastGood.empty()) c.lastGood = dir / lastGood;
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"penumbra-kiosk: the showroom kiosk on the board (docs/kiosk.md)"};
  std::string configPath;
  uint32_t frames = 0;
  apps::RenderFlags flags;
  app.add_option("CONFIG", configPath, "kiosk configuration (.json)")->required();
  app.add_option("--frames", frames, "stop after N frames (default: run until closed)");
  apps::addRenderFlags(&app, flags);
  CLI11_PARSE(app, argc, argv);

  platform::KioskLog log(stderr);
  try {
    const Config config = loadConfig(configPath);
    platform::SteadyTimebase time;
    const platform::GuardedBundle guarded = platform::loadBundleKeepingLastGood(
        config.bundle, config.lastGood, log, time.nowNanoseconds());
    const shadow::SceneBundle& b = guarded.bundle;
    auto fallback = [&](const std::string& what) {
      log.write(time.nowNanoseconds(), platform::LogLevel::kWarning, what);
    };

    std::unique_ptr<platform::FrameSource> camera;
    if (config.camera == "auto" || config.camera == "libcamera") {
#ifdef PENUMBRA_HAVE_LIBCAMERA
      try {
        const std::string id = platform::requireLibcameraCamera();
        fallback("camera: libcamera lists " + id +
                 " but libcamera capture is not implemented yet; trying V4L2");
      } catch (const platform::HardwareUnavailable& e) {
        fallback(e.what());
      }
#else
      fallback("camera: built without libcamera");
#endif
    }
    if (config.camera != "none") {
      const std::string dev = config.camera.rfind("/dev/", 0) == 0 ? config.camera : "/dev/video0";
#ifdef PENUMBRA_HAVE_OPENCV_CAMERA
      try {
        camera = std::make_unique<platform::OpenCvCamera>(dev, b.view.width, b.view.height);
      } catch (const platform::HardwareUnavailable& e) {
        fallback(std::string(e.what()) + "; showing the calibration photograph");
      }
#else
      fallback("camera: built without OpenCV (V4L2); showing the calibration photograph");
#endif
    }

    platform::RecordingLed noLed;
    platform::StatusLed* led = &noLed;
    std::unique_ptr<platform::ButtonSource> buttons;
#ifdef PENUMBRA_HAVE_GPIOD
    std::unique_ptr<platform::GpiodLed> gpioLed;
    platform::GpioConfig gpio;
    gpio.chip = config.gpioChip;
    try {
      buttons = std::make_unique<platform::GpiodButtons>(gpio);
      gpioLed = std::make_unique<platform::GpiodLed>(gpio);
      led = gpioLed.get();
    } catch (const platform::HardwareUnavailable& e) {
      fallback(std::string(e.what()) + "; no buttons, no status LED");
    }
#else
    fallback("gpio: built without libgpiod; no buttons, no status LED");
#endif

    std::unique_ptr<platform::Display> display;
    if (config.display == "sdl") {
#ifdef PENUMBRA_HAVE_SDL2
      try {
        display =
            std::make_unique<platform::SdlDisplay>(b.view.width, b.view.height, config.fullscreen);
      } catch (const platform::HardwareUnavailable& e) {
        fallback(std::string(e.what()) + "; running without a screen");
      }
#else
      fallback("display: built without SDL2; running without a screen");
#endif
    }

    platform::Peripherals io;
    io.camera = camera.get();
    io.buttons = buttons.get();
    io.led = led;
    io.display = display.get();
    io.time = &time;
    io.log = &log;
    platform::KioskLoop loop(b, platform::KioskOptions{}, io, apps::toOptions(flags));
    uint32_t shown = 0;
    for (;;) {
      const platform::FrameReport r = loop.step();
      ++shown;
      if (r.quit || (frames != 0 && shown >= frames)) break;
    }
    std::cout << "penumbra-kiosk: " << shown << " frames\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "penumbra-kiosk: error: " << e.what() << "\n";
    return 1;
  }
}
