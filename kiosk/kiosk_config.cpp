#include "kiosk/kiosk_config.h"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

namespace penumbra::kiosk {

namespace {

using nlohmann::json;

void refuseUnknown(const json& j, const std::set<std::string>& known, const std::string& where) {
  for (const auto& [k, v] : j.items()) {
    if (!known.count(k) && k.rfind("_comment", 0) != 0) {
      throw ConfigError(where + k + ": unknown key");
    }
  }
}

// camera_controls: {"exposure_us": 10000, "analogue_gain": 1.0, "colour_gains": [r, b]}.
CameraControls parseControls(const json& j, const std::string& where) {
  if (!j.is_object()) throw ConfigError(where + ": must be an object");
  refuseUnknown(j, {"exposure_us", "analogue_gain", "colour_gains"}, where + ".");
  CameraControls c;
  if (j.contains("exposure_us")) {
    if (!j["exposure_us"].is_number_integer()) {
      throw ConfigError(where + ".exposure_us: must be an integer");
    }
    const int64_t us = j["exposure_us"].get<int64_t>();
    c.exposureUs = static_cast<int32_t>(std::clamp<int64_t>(us, -1, 100'000'000));
  }
  if (j.contains("analogue_gain")) {
    if (!j["analogue_gain"].is_number())
      throw ConfigError(where + ".analogue_gain: must be a number");
    c.analogueGain = j["analogue_gain"].get<float>();
  }
  if (j.contains("colour_gains")) {
    const json& g = j["colour_gains"];
    if (!g.is_array() || g.size() != 2 || !g[0].is_number() || !g[1].is_number()) {
      throw ConfigError(where + ".colour_gains: must be [red, blue] numbers");
    }
    c.redGain = g[0].get<float>();
    c.blueGain = g[1].get<float>();
  }
  if (const std::string why = checkControls(c); !why.empty()) throw ConfigError(where + ": " + why);
  return c;
}

}  // namespace

KioskConfig loadKioskConfig(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream in(path);
  if (!in) throw ConfigError(file + ": cannot open");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    throw ConfigError(file + ": not valid JSON (" + e.what() + ")");
  }
  if (!j.is_object()) throw ConfigError(file + ": must be an object");
  refuseUnknown(j,
                {"bundle", "last_good_bundle", "camera", "camera_id", "camera_controls",
                 "camera_fallback", "gpio_chip", "display", "fullscreen", "product_files"},
                file + ": ");
  auto str = [&](const char* key, std::string& out) {
    if (!j.contains(key)) return;
    if (!j[key].is_string()) throw ConfigError(file + ": " + key + ": must be a string");
    out = j[key].get<std::string>();
  };
  KioskConfig c;
  std::string bundle, lastGood;
  str("bundle", bundle);
  if (bundle.empty()) throw ConfigError(file + ": bundle: required");
  str("last_good_bundle", lastGood);
  str("camera", c.camera);
  str("camera_id", c.cameraId);
  str("camera_fallback", c.cameraFallback);
  str("gpio_chip", c.gpioChip);
  str("display", c.display);
  if (c.camera != "auto" && c.camera != "libcamera" && c.camera != "none" &&
      c.camera.rfind("/dev/", 0) != 0) {
    throw ConfigError(file + ": camera: 'auto', 'libcamera', '/dev/videoN' or 'none', not '" +
                      c.camera + "'");
  }
  if (c.cameraFallback != "photograph" && c.cameraFallback != "simulated") {
    throw ConfigError(file + ": camera_fallback: 'photograph' or 'simulated', not '" +
                      c.cameraFallback + "'");
  }
  if (c.display != "sdl" && c.display != "none") {
    throw ConfigError(file + ": display: 'sdl' or 'none', not '" + c.display + "'");
  }
  if (j.contains("camera_controls")) {
    c.cameraControls = parseControls(j["camera_controls"], file + ": camera_controls");
  }
  if (j.contains("fullscreen")) {
    if (!j["fullscreen"].is_boolean())
      throw ConfigError(file + ": fullscreen: must be true or false");
    c.fullscreen = j["fullscreen"].get<bool>();
  }
  const std::filesystem::path dir = path.parent_path();
  if (j.contains("product_files")) {
    const json& list = j["product_files"];
    if (!list.is_array()) throw ConfigError(file + ": product_files: must be an array");
    for (size_t i = 0; i < list.size(); ++i) {
      const std::string where = file + ": product_files[" + std::to_string(i) + "]";
      const json& e = list[i];
      if (!e.is_object() || !e.contains("product") || !e.contains("file") ||
          !e["product"].is_string() || !e["file"].is_string()) {
        throw ConfigError(where + ": must be {\"product\": name, \"file\": path}");
      }
      refuseUnknown(e, {"product", "file"}, where + ".");
      c.productFiles.push_back(
          {e["product"].get<std::string>(), dir / e["file"].get<std::string>()});
    }
  }
  c.bundle = dir / bundle;
  if (!lastGood.empty()) c.lastGood = dir / lastGood;
  return c;
}

}  // namespace penumbra::kiosk
