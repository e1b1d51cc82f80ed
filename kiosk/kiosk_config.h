// The board program's configuration file (docs/kiosk.md, "The board program"): which
// bundle, which camera with which fixed controls, what to fall back to, GPIO chip, screen,
// and the environment camera of live lighting.
// Strict: unknown keys, wrong types and out-of-range values are refused with a ConfigError
// naming the file and the key. Paths are resolved against the file's folder.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "core/error.h"
#include "core/json_reader.h"
#include "kiosk/buttons.h"
#include "kiosk/environment_camera.h"
#include "kiosk/exposure_control.h"
#include "kiosk/kiosk_loop.h"
#include "kiosk/product_files.h"

namespace penumbra::kiosk {

class ConfigError : public core::Error {
 public:
  using core::Error::Error;
};

// docs/kiosk.md's wiring table (BCM numbers), in Button order (next, previous, left, right,
// forward, back, rotate, quality), and the status LED's line.
inline constexpr std::array<uint32_t, kButtonCount> kDefaultButtonLines{5,  6,  13, 19,
                                                                        26, 16, 20, 21};
inline constexpr int32_t kDefaultLedLine = 12;

struct KioskConfig {
  std::filesystem::path bundle, lastGood;
  std::string camera = "auto";  // auto | libcamera | /dev/videoN | none
  std::string cameraId;         // libcamera id; empty: the first camera
  CameraControls cameraControls;
  // After libcamera and V4L2: "photograph" (the bundle's still, "NO CAMERA" on the HUD) or
  // "simulated" (the simulated camera of firmware-sim filming that still).
  std::string cameraFallback = "photograph";
  std::string gpioChip = "/dev/gpiochip0";
  std::array<uint32_t, kButtonCount> buttonLines = kDefaultButtonLines;
  int32_t ledLine = kDefaultLedLine;  // -1: no LED
  // Render threads; 0: one per core the kiosk may run on.
  int threads = 0;
  // Frame rates, passes, attract mode, buttons, HUD (readLoopOptions). A site's HUD defaults to
  // "service": customers see the room and the product, not the frame rate.
  KioskOptions loop;
  // "drm": straight on the kernel's display (platform/drm_display.h), the board's choice;
  // "sdl": SDL2 (a window on a desktop, KMSDRM through EGL on a board); "none".
  std::string display = "sdl";
  std::string drmDevice;   // "drm" only; empty: the first /dev/dri/card* with a screen
  bool fullscreen = true;  // "sdl" only
  // Product models from files (kiosk/product_files.h), watched while the kiosk runs.
  std::vector<ProductFile> productFiles;
  // "environment": live lighting from the real environment camera (absent: captured light;
  // its light options are in `loop`, readLiveLightOptions).
  std::optional<EnvironmentCameraSettings> environment;
};

KioskConfig loadKioskConfig(const std::filesystem::path& path);

// The loop's options from the object `key` of `parent` (absent: the defaults), shared by the
// configuration's "loop" and a simulator session's "kiosk" (docs/kiosk.md): frame rates, pass
// limits, attract mode, buttons, HUD ("on", "off", "service"). Throws through the document's
// error type naming the key. `hudDefault` is the HUD when the object does not say.
KioskOptions readLoopOptions(const core::JsonValue& parent, std::string_view key,
                             HudMode hudDefault);

// Live lighting's options (issue 16) from an "environment" object `e` (docs/kiosk.md) into
// `o`: "samples" (Halton samples per map, 1..4096), "lights" (the most lights, one shadow
// pass each, 1..256 and at most samples; the loop's max_passes caps a frame's), "yaw_deg"
// (the environment camera's azimuth 0 in the room: its image's +x turned this far from the
// room's +x about +y; the camera looks at the zenith), "radiance_scale" (its radiance units
// in the room camera's, > 0), "stale_after_ms". Keys other than these are the caller's to
// allow (`e.object(...)` before this call).
void readLiveLightOptions(const core::JsonValue& e, KioskOptions& o);

// The environment camera's exposure bracket: at most this many times, each at most 1 s; a
// device drops at most kMostSettleFrames frames after each change.
inline constexpr size_t kMostBracketExposures = 8;
inline constexpr int64_t kLongestBracketExposureUs = 1'000'000;
inline constexpr int64_t kMostSettleFrames = 30;

// The configuration's "environment" object (docs/kiosk.md, "Environment camera"): "device"
// (a /dev/videoN, or a video file or image sequence relative to `dir`), "width", "height"
// (2..4096), "lens" ("equidistant180", or {"fx", "fy", "cx", "cy", "k": [k1, k2, k3, k4]}),
// "response" ("srgb", a gamma, 1..4, or a response file relative to `dir` written by
// `penumbra camera-response`, read and checked here; default "srgb"), "exposure_scale" (> 0,
// default 1), "bracket_us" (1..8 exposure times in µs, increasing, each ≤ 1 s; a device's in
// steps of 100 µs), "settle_frames" (a device with a bracket only; 0..30, default 2), and
// the light options of readLiveLightOptions into `o`. Strict, like the rest.
EnvironmentCameraSettings readEnvironmentCamera(const core::JsonValue& e,
                                                const std::filesystem::path& dir, KioskOptions& o);

}  // namespace penumbra::kiosk
