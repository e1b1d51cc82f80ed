#include "kiosk/kiosk_config.h"

#include <algorithm>
#include <array>
#include <cstdint>

#include "core/json_reader.h"

namespace penumbra::kiosk {

namespace {

using core::JsonValue;

// camera_controls: {"exposure_us": 10000, "analogue_gain": 1.0, "colour_gains": [r, b]}.
CameraControls parseControls(const JsonValue& j) {
  j.object({"exposure_us", "analogue_gain", "colour_gains"});
  CameraControls c;
  if (const auto us = j.find("exposure_us")) {
    const int64_t v = us->integer(INT64_MIN, INT64_MAX);
    c.exposureUs = static_cast<int32_t>(std::clamp<int64_t>(v, -1, 100'000'000));
  }
  if (const auto gain = j.find("analogue_gain")) {
    c.analogueGain = static_cast<float>(gain->number());
  }
  if (const auto gains = j.find("colour_gains")) {  // [red, blue]
    const std::array<float, 2> redBlue = gains->floats<2>();
    c.redGain = redBlue[0];
    c.blueGain = redBlue[1];
  }
  if (const std::string why = checkControls(c); !why.empty()) j.fail(why);
  return c;
}

// The configuration keeps these choices by name.
std::string oneOfNames(const JsonValue& v, std::initializer_list<std::string_view> names) {
  return std::string(*(names.begin() + v.oneOf(names)));
}

}  // namespace

KioskConfig loadKioskConfig(const std::filesystem::path& path) {
  const core::JsonDocument doc(path, core::throwAs<ConfigError>);
  const JsonValue j =
      doc.root().object({"bundle", "last_good_bundle", "camera", "camera_id", "camera_controls",
                         "camera_fallback", "gpio_chip", "display", "fullscreen", "product_files"});
  KioskConfig c;
  const std::string bundle = j.stringOr("bundle", "");
  if (bundle.empty()) doc.fail("bundle", "required");
  const std::string lastGood = j.stringOr("last_good_bundle", "");
  c.camera = j.stringOr("camera", c.camera);
  c.cameraId = j.stringOr("camera_id", c.cameraId);
  c.gpioChip = j.stringOr("gpio_chip", c.gpioChip);
  if (c.camera != "auto" && c.camera != "libcamera" && c.camera != "none" &&
      c.camera.rfind("/dev/", 0) != 0) {
    j["camera"].fail("'auto', 'libcamera', '/dev/videoN' or 'none', not '" + c.camera + "'");
  }
  if (const auto fallback = j.find("camera_fallback")) {
    c.cameraFallback = oneOfNames(*fallback, {"photograph", "simulated"});
  }
  if (const auto display = j.find("display")) c.display = oneOfNames(*display, {"sdl", "none"});
  if (const auto controls = j.find("camera_controls")) c.cameraControls = parseControls(*controls);
  c.fullscreen = j.booleanOr("fullscreen", c.fullscreen);
  const std::filesystem::path dir = path.parent_path();
  if (const auto list = j.find("product_files")) {
    for (const JsonValue& e : list->array()) {
      e.object({"product", "file"});
      c.productFiles.push_back({e["product"].string(), dir / e["file"].string()});
    }
  }
  c.bundle = dir / bundle;
  if (!lastGood.empty()) c.lastGood = dir / lastGood;
  return c;
}

}  // namespace penumbra::kiosk
