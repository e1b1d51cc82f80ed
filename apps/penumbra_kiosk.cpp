// `penumbra-kiosk CONFIG.json [--bracket DIR | --check]`, `penumbra-kiosk --list-cameras`: the
// board program (issue 6, docs/kiosk.md).
// The kiosk loop of platform/ with the real peripherals, each falling back when absent:
// camera libcamera → V4L2 webcam (OpenCV) → the simulated camera if configured → the
// calibration photograph;
// buttons and LED on libgpiod → none (attract mode only); screen SDL2 → none (frames are
// rendered and counted, for a headless check); the environment camera of live lighting
// (configured: an 8-bit fisheye through the OpenCV module) → the bundle's captured light.
// Every fallback is logged to stderr (journald).
#include <CLI/CLI.hpp>
#include <csignal>
#include <functional>
#include <iomanip>
#include <iostream>
#include <memory>

#include "apps/kiosk_check.h"
#include "apps/render_flags.h"
#include "core/cli.h"
#include "core/process_memory.h"
#include "firmware-sim/virtual_camera.h"
#include "kiosk/bundle_guard.h"
#include "kiosk/exposure_control.h"
#include "kiosk/kiosk_config.h"
#include "kiosk/kiosk_loop.h"
#include "platform/hardware.h"
#include "platform/opencv_environment_camera.h"
#include "platform/service_notifier.h"
#ifdef PENUMBRA_HAVE_GPIOD
#include "platform/gpiod_io.h"
#endif
#ifdef PENUMBRA_HAVE_LIBCAMERA
#include "platform/libcamera_camera.h"
#endif
#ifdef PENUMBRA_HAVE_OPENCV_CAMERA
#include "platform/opencv_camera_module.h"
#endif
#ifdef PENUMBRA_HAVE_DRM
#include "platform/drm_display.h"
#endif
#ifdef PENUMBRA_HAVE_SDL2
#include "platform/sdl_display.h"
#endif

using namespace penumbra;

namespace {

// SIGTERM (systemctl stop) and SIGINT end the frame loop after the frame being drawn, so the
// camera is stopped and the log flushed as on any other exit.
volatile std::sig_atomic_t stopRequested = 0;
void requestStop(int) {
  stopRequested = 1;
}

// The configured screen (docs/kiosk.md, "The screen"), or none: a screen that cannot open,
// or a build without its library, is one `warn` line and the kiosk runs without a screen.
std::unique_ptr<kiosk::Display> openScreen(
    const kiosk::KioskConfig& config, uint32_t width, uint32_t height,
    const std::function<void(std::string)>& warn,
    [[maybe_unused]] const std::function<void(std::string)>& info) {
  [[maybe_unused]] const std::string frame = std::to_string(width) + "x" + std::to_string(height);
  try {
    if (config.display == "drm") {
#ifdef PENUMBRA_HAVE_DRM
      auto drm = std::make_unique<platform::DrmDisplay>(config.drmDevice, width, height);
      info("display: " + drm->description() + ", frame " + frame);
      return drm;
#else
      throw platform::HardwareUnavailable("display: built without libdrm");
#endif
    }
    if (config.display == "sdl") {
#ifdef PENUMBRA_HAVE_SDL2
      auto sdl = std::make_unique<platform::SdlDisplay>(width, height, config.fullscreen);
      // SDL falls back to drivers that show nothing when no screen answers: say so, or a
      // technician sees a black screen and a log without a word about it.
      const std::string driver = sdl->driver();
      if (sdl->showsNothing()) {
        warn("display: SDL chose its '" + driver +
             "' video driver, which shows nothing on a screen; set SDL_VIDEODRIVER=kmsdrm "
             "(or x11, wayland)");
      } else {
        info("display: SDL " + driver + " " + frame);
      }
      return sdl;
#else
      throw platform::HardwareUnavailable("display: built without SDL2");
#endif
    }
  } catch (const platform::HardwareUnavailable& e) {
    warn(std::string(e.what()) + "; running without a screen");
  }
  return nullptr;
}

// The camera, in the fallback order of docs/kiosk.md: libcamera → V4L2 webcam (OpenCV) →
// the simulated camera if configured → none (the bundle's photograph, said on the HUD).
// Each step that fails is logged with its reason.
std::unique_ptr<kiosk::FrameSource> openCamera(const kiosk::KioskConfig& config,
                                               const shadow::SceneBundle& b,
                                               const std::function<void(std::string)>& warn) {
  if (config.camera == "none") return nullptr;
  if (config.camera == "auto" || config.camera == "libcamera") {
#ifdef PENUMBRA_HAVE_LIBCAMERA
    try {
      platform::LibcameraOptions o;
      o.cameraId = config.cameraId;
      o.width = b.view.width;
      o.height = b.view.height;
      o.controls = config.cameraControls;
      return std::make_unique<platform::LibcameraCamera>(o);
    } catch (const platform::HardwareUnavailable& e) {
      warn(std::string(e.what()) + "; trying V4L2");
    }
#else
    warn("camera: built without libcamera; trying V4L2");
#endif
  }
  if (config.camera != "libcamera") {
    const std::string dev = config.camera.rfind("/dev/", 0) == 0 ? config.camera : "/dev/video0";
#ifdef PENUMBRA_HAVE_OPENCV_CAMERA
    try {
      return platform::openOpenCvCamera(dev, b.view.width, b.view.height);
    } catch (const platform::HardwareUnavailable& e) {
      warn(e.what());
    }
#else
    warn("camera: built without OpenCV (V4L2), " + dev + " not tried");
#endif
  }
  if (config.cameraFallback == "simulated") {
    warn("camera: using the simulated camera (camera_fallback: simulated)");
    return std::make_unique<firmware_sim::VirtualCamera>(b.background, b.view.width, b.view.height,
                                                         firmware_sim::CameraScript{});
  }
  warn("camera: none; showing the calibration photograph");
  return nullptr;
}

// Live lighting's environment camera ("environment" in the configuration): the 8-bit fisheye
// through the OpenCV module. Anything that keeps it from opening (no device, no module, a lens
// that does not see the hemisphere) is one line in the log, and the kiosk lights the product
// with the bundle's captured light.
std::unique_ptr<kiosk::EnvironmentCamera> openEnvironment(
    const kiosk::KioskConfig& config, const platform::EnvironmentLog& say,
    const std::function<void(std::string)>& warn) {
  if (!config.environment) return nullptr;
#ifdef PENUMBRA_HAVE_OPENCV_CAMERA
  try {
    return platform::openOpenCvEnvironmentCamera(*config.environment, say);
  } catch (const std::exception& e) {
    warn(std::string(e.what()) + "; live lighting off, the bundle's captured light");
  }
#else
  (void)say;
  warn("environment camera: built without OpenCV, " + config.environment->device +
       " not opened; live lighting off, the bundle's captured light");
#endif
  return nullptr;
}

// `--bracket DIR`: the exposure ladder around the configured exposure, written for
// `penumbra capture` (docs/capture.md). Needs a camera whose exposure can be fixed.
int bracket(const kiosk::KioskConfig& config, const shadow::SceneBundle& b,
            const std::filesystem::path& dir, uint32_t stops, kiosk::KioskLog& log) {
#ifdef PENUMBRA_HAVE_LIBCAMERA
  platform::LibcameraOptions o;
  o.cameraId = config.cameraId;
  o.width = b.view.width;
  o.height = b.view.height;
  o.controls = config.cameraControls;
  std::unique_ptr<platform::LibcameraCamera> camera;
  try {
    camera = std::make_unique<platform::LibcameraCamera>(o);
  } catch (const platform::HardwareUnavailable& e) {
    throw std::runtime_error(std::string("--bracket needs a libcamera camera with exposure "
                                         "control: ") +
                             e.what());
  }
  kiosk::SteadyTimebase time;
  kiosk::BracketOptions bo;
  bo.exposuresUs = kiosk::exposureLadder(config.cameraControls.exposureUs, stops);
  bo.base = config.cameraControls;
  bo.width = b.view.width;
  bo.height = b.view.height;
  bo.orientation = config.loop.cameraOrientation;
  const auto shots = kiosk::captureBracket(*camera, time, bo, log);
  kiosk::writeBracket(shots, b.view.width, b.view.height, dir);
  std::cout << "penumbra-kiosk: " << shots.size() << " exposures in " << dir.string()
            << " (exposures.json)\n";
  return 0;
#else
  (void)config, (void)b, (void)dir, (void)stops, (void)log;
  throw std::runtime_error(
      "--bracket needs a libcamera camera with exposure control; this "
      "build has no libcamera (PENUMBRA_WITH_LIBCAMERA)");
#endif
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"penumbra-kiosk: the showroom kiosk on the board (docs/kiosk.md)"};
  std::string configPath;
  uint32_t frames = 0;
  apps::RenderFlags flags;
  bool check = false, list = false;
  app.add_option("CONFIG", configPath, "kiosk configuration (.json)");
  app.add_flag("--check", check,
               "validate CONFIG, its bundle and product files, print what the kiosk would use "
               "and exit (1 on any error)");
  app.add_flag("--list-cameras", list, "list the libcamera cameras and V4L2 devices and exit");
  app.add_option("--frames", frames, "stop after N frames (default: run until closed)");
  std::string bracketDir;
  uint32_t stops = 7;
  app.add_option("--bracket", bracketDir,
                 "film an exposure bracket into DIR for `penumbra capture` and exit");
  app.add_option("--bracket-stops", stops, "exposures, one stop apart, around camera_controls")
      ->check(cli::NumberRange(2, 15));
  apps::addRenderFlags(&app, flags);
  app.get_option("--threads")
      ->description(
          "render threads (default: the configuration's `threads`; 0 there = one per "
          "core)")
      ->default_str("");
  // What a man page would say, for a technician on the board without the docs at hand.
  app.footer(R"(Files:
  /etc/penumbra/kiosk.json  the configuration (keys: docs/kiosk.md, "The board program")
  /usr/share/penumbra/showroom/showroom.bundle  the bundled showroom
  /var/lib/penumbra/        the last good bundle and its trial mark
Environment:
  SDL_VIDEODRIVER           kmsdrm on a board; offscreen and dummy show nothing (logged)
  NOTIFY_SOCKET, WATCHDOG_USEC  set by systemd (Type=notify): READY, WATCHDOG, STOPPING
Signals:
  SIGTERM, SIGINT           end the frame loop after the frame being drawn (exit 0)
Exit status:
  0 ok; 1 runtime error (configuration, bundle, product file, camera for --bracket);
  2 usage error
Examples:
  penumbra-kiosk --check /etc/penumbra/kiosk.json
  penumbra-kiosk --list-cameras
  sudo systemctl restart penumbra-kiosk; journalctl -u penumbra-kiosk)");
  kiosk::KioskLog log(stderr);
  return cli::run("penumbra-kiosk", app, argc, argv, [&] {
    if (list) {
      apps::listCameras(std::cout);
      return 0;
    }
    if (configPath.empty()) throw cli::UsageError("CONFIG is required (or --list-cameras)");
    if (check) {
      apps::checkKioskConfig(configPath, std::cout);
      return 0;
    }
    const kiosk::KioskConfig config = kiosk::loadKioskConfig(configPath);
    // --threads on the command line wins over the configuration's `threads`.
    raster::RenderOptions render = apps::toOptions(flags);
    if (app.get_option("--threads")->count() == 0) render.threads = apps::kioskThreads(config);
    kiosk::SteadyTimebase time;
    kiosk::GuardedBundle guarded = kiosk::loadBundleKeepingLastGood(config.bundle, config.lastGood,
                                                                    log, time.nowNanoseconds());
    // Product files replace the bundle's models before the carousel is built; refused ones
    // keep the bundle's model (docs/kiosk.md, faults).
    kiosk::ProductFileWatcher productFiles(config.productFiles);
    const auto startupChanges = productFiles.poll(guarded.bundle, log, time.nowNanoseconds());
    const shadow::SceneBundle& b = guarded.bundle;
    auto fallback = [&](const std::string& what) {
      log.write(time.nowNanoseconds(), kiosk::LogLevel::kWarning, what);
    };

    if (!bracketDir.empty()) return bracket(config, b, bracketDir, stops, log);
    const std::unique_ptr<kiosk::FrameSource> camera = openCamera(config, b, fallback);
    if (camera)
      log.write(time.nowNanoseconds(), kiosk::LogLevel::kInfo, "camera: " + camera->describe());
    const std::unique_ptr<kiosk::EnvironmentCamera> environment = openEnvironment(
        config,
        [&](kiosk::LogLevel level, const std::string& text) {
          log.write(time.nowNanoseconds(), level, text);
        },
        fallback);

    kiosk::RecordingLed noLed;
    kiosk::StatusLed* led = &noLed;
    std::unique_ptr<kiosk::ButtonSource> buttons;
#ifdef PENUMBRA_HAVE_GPIOD
    std::unique_ptr<platform::GpiodLed> gpioLed;
    platform::GpioConfig gpio;
    gpio.chip = config.gpioChip;
    gpio.lines = config.buttonLines;
    gpio.ledLine = config.ledLine;
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

    const std::unique_ptr<kiosk::Display> display =
        openScreen(config, b.view.width, b.view.height, fallback, [&](const std::string& what) {
          log.write(time.nowNanoseconds(), kiosk::LogLevel::kInfo, what);
        });

    kiosk::Peripherals io;
    io.camera = camera.get();
    io.environment = environment.get();
    io.buttons = buttons.get();
    io.led = led;
    io.display = display.get();
    io.time = &time;
    io.log = &log;
    log.write(time.nowNanoseconds(), kiosk::LogLevel::kInfo,
              "render: " + std::to_string(render.threads) + " threads");
    kiosk::KioskLoop loop(b, config.loop, io, render);
    auto tell = [&](const std::vector<kiosk::ProductFileWatcher::Change>& changes) {
      for (const auto& c : changes) {
        const std::string& name = b.products[c.product].name;
        loop.setFault(name, c.replaced ? std::string() : kiosk::productFileFault(name));
        if (c.replaced) loop.productReplaced(c.product);
      }
    };
    tell(startupChanges);
    // systemd (Type=notify, WatchdogSec=): ready once a frame is on the screen, alive every
    // frame after.
    platform::ServiceNotifier systemd;
    if (systemd.active()) {
      log.write(time.nowNanoseconds(), kiosk::LogLevel::kInfo,
                "systemd: notifying" +
                    (systemd.watchdogNs() > 0
                         ? ", watchdog " + std::to_string(systemd.watchdogNs() / 1'000'000) + " ms"
                         : std::string()));
    }
    std::signal(SIGTERM, requestStop);
    std::signal(SIGINT, requestStop);
    uint32_t shown = 0;
    int64_t nextPollNs = time.nowNanoseconds() + 1'000'000'000;
    while (stopRequested == 0) {
      if (!config.productFiles.empty() && time.nowNanoseconds() >= nextPollNs) {
        // Hot-swap: files are looked at once a second and loaded off the frame loop; the
        // old model stays on screen until a load is ready (kiosk/product_files.h).
        tell(productFiles.poll(guarded.bundle, log, time.nowNanoseconds(),
                               kiosk::ProductFileWatcher::Wait::kNo));
        nextPollNs = time.nowNanoseconds() + 1'000'000'000;
      } else if (productFiles.loading()) {
        tell(productFiles.collect(guarded.bundle, log, time.nowNanoseconds()));
      }
      const kiosk::FrameReport r = loop.step();
      kiosk::noteFrameRendered(guarded, log, time.nowNanoseconds());
      if (shown == 0) systemd.ready("showing " + b.products[r.pose.product].name);
      systemd.alive(time.nowNanoseconds());
      ++shown;
      if (r.quit || (frames != 0 && shown >= frames)) break;
    }
    if (stopRequested != 0) {
      systemd.stopping();
      log.write(time.nowNanoseconds(), kiosk::LogLevel::kInfo, "stopping: signal received");
    }
    // The memory budget of docs/kiosk.md ("Memory"): the peak over the whole run.
    const core::ProcessMemory memory = core::processMemory();
    std::cout << "penumbra-kiosk: " << shown << " frames, peak RSS " << std::fixed
              << std::setprecision(1) << double(memory.peakRssKb) / 1024.0 << " MB\n";
    return 0;
  });
}
