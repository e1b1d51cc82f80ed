// The board program's configuration file (docs/kiosk.md, "The board program"): which
// bundle, which camera with which fixed controls, what to fall back to, GPIO chip, screen.
// Strict: unknown keys, wrong types and out-of-range values are refused with a ConfigError
// naming the file and the key. Paths are resolved against the file's folder.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

#include "core/error.h"
#include "kiosk/exposure_control.h"
#include "kiosk/product_files.h"

namespace penumbra::kiosk {

class ConfigError : public core::Error {
 public:
  using core::Error::Error;
};

struct KioskConfig {
  std::filesystem::path bundle, lastGood;
  std::string camera = "auto";  // auto | libcamera | /dev/videoN | none
  std::string cameraId;         // libcamera id; empty: the first camera
  CameraControls cameraControls;
  // After libcamera and V4L2: "photograph" (the bundle's still, "NO CAMERA" on the HUD) or
  // "simulated" (the simulated camera of firmware-sim filming that still).
  std::string cameraFallback = "photograph";
  std::string gpioChip = "/dev/gpiochip0";
  std::string display = "sdl";  // sdl | none
  bool fullscreen = true;
  // Product models from files (kiosk/product_files.h), watched while the kiosk runs.
  std::vector<ProductFile> productFiles;
};

KioskConfig loadKioskConfig(const std::filesystem::path& path);

}  // namespace penumbra::kiosk
