#include "kiosk/kiosk_config.h"

#include "scene/portable_trig.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>

#include "core/json_reader.h"
#include "envmap/fisheye_lens_file.h"

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

constexpr int64_t kMs = 1'000'000;
constexpr int64_t kHour = 3'600'000;  // ms

// The configuration keeps these choices by name.
std::string oneOfNames(const JsonValue& v, std::initializer_list<std::string_view> names) {
  return std::string(*(names.begin() + v.oneOf(names)));
}

// gpio_lines: {"next": 5, ...} (any subset; the rest keep the wiring table's) and led_line
// (-1: none). Two functions on one line would read one press as both.
void readGpioLines(const JsonValue& j, KioskConfig& c) {
  if (const auto lines = j.find("gpio_lines")) {
    for (const auto& [name, value] : lines->object().members()) {
      const auto b = parseButton(name);
      if (!b)
        value.fail("not a button (next, previous, left, right, forward, back, rotate, quality)");
      c.buttonLines[static_cast<size_t>(*b)] = static_cast<uint32_t>(value.integer(0, 1023));
    }
  }
  c.ledLine = static_cast<int32_t>(j.integerOr("led_line", c.ledLine, -1, 1023));
  for (size_t a = 0; a < kButtonCount; ++a) {
    const char* name = buttonName(static_cast<Button>(a));
    for (size_t b = a + 1; b < kButtonCount; ++b) {
      if (c.buttonLines[a] == c.buttonLines[b]) {
        j["gpio_lines"].fail(std::string(name) + " and " + buttonName(static_cast<Button>(b)) +
                             " are both on line " + std::to_string(c.buttonLines[a]));
      }
    }
    if (int64_t(c.buttonLines[a]) == c.ledLine) {
      j[j.has("led_line") ? "led_line" : "gpio_lines"].fail(std::string("the LED and the ") + name +
                                                            " button are both on line " +
                                                            std::to_string(c.ledLine));
    }
  }
}

}  // namespace

KioskOptions readLoopOptions(const JsonValue& parent, std::string_view key, HudMode hudDefault) {
  const JsonValue k = parent.optionalObject(
      key, {"fps", "quality_fps", "fixed_cost_us", "min_passes", "max_passes", "initial_passes",
            "attract_after_ms", "attract_mdeg_per_s", "move_step_m", "rotate_step_deg",
            "stale_after_ms", "reopen_every_ms", "debounce_ms", "stuck_after_ms", "hud",
            "service_hold_ms", "full_detail_px", "texels_per_pixel"});
  KioskOptions o;
  o.hud = hudDefault;
  const int64_t fps = k.integerOr("fps", 30, 1, 240);
  const int64_t qfps = k.integerOr("quality_fps", 15, 1, 240);
  o.fastFrameNs = 1'000'000'000 / fps;
  o.qualityFrameNs = 1'000'000'000 / qfps;
  o.fixedCostNs = k.integerOr("fixed_cost_us", 0, 0, 10'000'000) * 1000;
  if (o.fixedCostNs >= o.fastFrameNs || o.fixedCostNs >= o.qualityFrameNs) {
    k["fixed_cost_us"].fail("must be below the frame time of both modes");
  }
  o.minPasses = static_cast<uint32_t>(k.integerOr("min_passes", 4, 1, 256));
  o.maxPasses = static_cast<uint32_t>(k.integerOr("max_passes", 64, 1, 256));
  if (o.minPasses > o.maxPasses) k["min_passes"].fail("must be <= max_passes");
  o.initialPasses = static_cast<uint32_t>(k.integerOr("initial_passes", 8, 0, 256));
  if (o.initialPasses != 0 && (o.initialPasses < o.minPasses || o.initialPasses > o.maxPasses)) {
    k["initial_passes"].fail("must be 0 or in [min_passes, max_passes]");
  }
  o.footprintDetail.fullDetailPx =
      static_cast<uint32_t>(k.integerOr("full_detail_px", 48, 0, 100'000));
  o.footprintDetail.texelsPerPixel =
      static_cast<uint32_t>(k.integerOr("texels_per_pixel", 4, 1, 64));
  o.attractAfterNs = k.integerOr("attract_after_ms", 20'000, 1, kHour) * kMs;
  o.attractMilliDegreesPerSecond =
      static_cast<uint32_t>(k.integerOr("attract_mdeg_per_s", 12'000, 0, 3'600'000));
  o.moveStepMetres = static_cast<float>(k.numberOr("move_step_m", 0.1, 0.001, 2.0));
  o.rotateStepDegrees = static_cast<float>(k.numberOr("rotate_step_deg", 15.0, 0.1, 180.0));
  o.staleAfterNs = k.integerOr("stale_after_ms", 100, 1, 60'000) * kMs;
  o.reopenEveryNs = k.integerOr("reopen_every_ms", 1000, 1, 60'000) * kMs;
  o.debounce.settleNs = k.integerOr("debounce_ms", 20, 0, 1000) * kMs;
  o.debounce.stuckNs = k.integerOr("stuck_after_ms", 5000, 1, kHour) * kMs;
  if (o.debounce.stuckNs <= o.debounce.settleNs) {
    k["stuck_after_ms"].fail("must be longer than debounce_ms");
  }
  if (const auto hud = k.find("hud")) {
    o.hud = hud->oneOf<HudMode>(
        {{"on", HudMode::kOn}, {"off", HudMode::kOff}, {"service", HudMode::kService}});
  }
  o.serviceHoldNs = k.integerOr("service_hold_ms", 3000, 500, 60'000) * kMs;
  if (o.hud == HudMode::kService && o.serviceHoldNs >= o.debounce.stuckNs) {
    k[k.has("service_hold_ms") ? "service_hold_ms" : "stuck_after_ms"].fail(
        "the service hold (" + std::to_string(o.serviceHoldNs / kMs) +
        " ms) must be shorter than stuck_after_ms (" + std::to_string(o.debounce.stuckNs / kMs) +
        " ms): a longer hold is taken as a stuck button");
  }
  return o;
}

KioskConfig loadKioskConfig(const std::filesystem::path& path) {
  const core::JsonDocument doc(path, core::throwAs<ConfigError>);
  const JsonValue j = doc.root().object(
      {"bundle", "last_good_bundle", "camera", "camera_id", "camera_controls", "camera_fallback",
       "camera_rotation", "camera_flip", "gpio_chip", "gpio_lines", "led_line", "display",
       "drm_device", "fullscreen", "product_files", "threads", "loop", "environment"});
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
  if (const auto display = j.find("display")) {
    c.display = oneOfNames(*display, {"drm", "sdl", "none"});
  }
  c.drmDevice = j.stringOr("drm_device", c.drmDevice);
  if (!c.drmDevice.empty() && c.display != "drm") {
    j["drm_device"].fail("is for display \"drm\", and display is \"" + c.display + "\"");
  }
  if (const auto controls = j.find("camera_controls")) c.cameraControls = parseControls(*controls);
  c.fullscreen = j.booleanOr("fullscreen", c.fullscreen);
  c.threads = static_cast<int>(j.integerOr("threads", 0, 0, 64));
  readGpioLines(j, c);
  c.loop = readLoopOptions(j, "loop", HudMode::kService);
  // A sensor mounted upside down is turned by 180°, i.e. mirrored on both axes; a flip
  // mirrors one more time.
  const int64_t rotation = j.integerOr("camera_rotation", 0, 0, 180);
  if (rotation % 180 != 0) {
    j["camera_rotation"].fail("expected 0 or 180, got " + std::to_string(rotation) +
                              " (a quarter turn would swap the calibrated view's width and "
                              "height)");
  }
  const bool turned = rotation == 180;
  std::string flip = "none";
  if (const auto f = j.find("camera_flip"))
    flip = oneOfNames(*f, {"none", "horizontal", "vertical"});
  c.loop.cameraOrientation.mirrorX = turned != (flip == "horizontal");
  c.loop.cameraOrientation.mirrorY = turned != (flip == "vertical");
  const std::filesystem::path dir = path.parent_path();
  if (const auto list = j.find("product_files")) {
    for (const JsonValue& e : list->array()) {
      e.object({"product", "file"});
      c.productFiles.push_back({e["product"].string(), dir / e["file"].string()});
    }
  }
  if (const auto e = j.find("environment")) {
    c.environment = readEnvironmentCamera(*e, dir, c.loop);
    if (c.environment->device == c.camera) {
      (*e)["device"].fail("the room camera is " + c.camera +
                          " too: a V4L2 device serves one of them");
    }
  }
  c.bundle = dir / bundle;
  if (!lastGood.empty()) c.lastGood = dir / lastGood;
  return c;
}

void readLiveLightOptions(const JsonValue& e, KioskOptions& o) {
  envmap::LiveLightsOptions& l = o.liveLights;
  l.samples = static_cast<uint32_t>(e.integerOr("samples", l.samples, 1, 4096));
  l.maxLights = static_cast<uint32_t>(e.integerOr("lights", l.maxLights, 1, 256));
  if (l.maxLights > l.samples) e["lights"].fail("must not exceed samples");
  // The camera's frame: z along its optical axis (the zenith, world +y), x its image's right.
  // Turned by yaw about +y, x goes to (cos, 0, sin) and y = z × x to (sin, 0, -cos): a
  // rotation (right-handed, orthonormal), from portable sine and cosine.
  double s = 0, c = 1;
  scene::sinCosDegrees(e.numberOr("yaw_deg", 0.0, -360.0, 360.0), s, c);
  l.toWorld = glm::dmat3(glm::dvec3(c, 0, s), glm::dvec3(s, 0, -c), glm::dvec3(0, 1, 0));
  l.radianceScale = e.numberOr("radiance_scale", l.radianceScale, 1e-9, 1e9);
  o.environmentStaleAfterNs =
      e.integerOr("stale_after_ms", o.environmentStaleAfterNs / 1'000'000, 1, 60'000) * 1'000'000;
}

namespace {

// "bracket_us" and "settle_frames" (docs/kiosk.md, "Environment camera").
void readBracket(const JsonValue& e, EnvironmentCameraSettings& s) {
  const bool device = s.device.rfind("/dev/", 0) == 0;
  if (const auto b = e.find("bracket_us")) {
    for (const JsonValue& t : b->array(1, kMostBracketExposures)) {
      const int64_t us = t.integer(1, kLongestBracketExposureUs);
      if (!s.bracketUs.empty() && us <= s.bracketUs.back()) {
        t.fail("must be longer than the exposure before it (" + std::to_string(s.bracketUs.back()) +
               " us): the bracket is listed shortest first, each time once");
      }
      // OpenCV's V4L2 backend passes CAP_PROP_EXPOSURE unscaled to exposure_time_absolute,
      // whose unit is 100 µs: another time would be rounded, and the merge would divide by
      // a time the sensor did not use.
      if (device && us % 100 != 0) {
        t.fail(
            "a V4L2 device's exposure is set in steps of 100 us (exposure_time_absolute), "
            "got " +
            std::to_string(us));
      }
      s.bracketUs.push_back(us);
    }
  }
  if (const auto settle = e.find("settle_frames")) {
    if (s.bracketUs.empty()) settle->fail("only with bracket_us");
    if (!device) {
      settle->fail("only for a device: frame i of a recording was shot with bracket_us[i % n]");
    }
    s.settleFrames = static_cast<uint32_t>(settle->integer(0, kMostSettleFrames));
  }
}

}  // namespace

EnvironmentCameraSettings readEnvironmentCamera(const JsonValue& e,
                                                const std::filesystem::path& dir, KioskOptions& o) {
  e.object({"device", "width", "height", "lens", "response", "exposure_scale", "bracket_us",
            "settle_frames", "samples", "lights", "yaw_deg", "radiance_scale", "stale_after_ms"});
  EnvironmentCameraSettings s;
  s.device = e["device"].nonEmptyString();
  // A device node stays as given; a recording is a path like the configuration's others.
  if (s.device.rfind("/dev/", 0) != 0) s.device = (dir / s.device).string();
  s.width = static_cast<uint32_t>(e["width"].integer(2, 4096));
  s.height = static_cast<uint32_t>(e["height"].integer(2, 4096));
  const JsonValue lens = e["lens"];
  if (!lens.json().is_string() && !lens.json().is_object()) {
    lens.fail(
        R"(expected "equidistant180", a lens file or {"fx", "fy", "cx", "cy", "k": [k1, k2, k3, k4]})");
  }
  if (lens.json().is_string()) {
    const std::string name = lens.nonEmptyString();
    if (name == "equidistant180") {
      s.lens = envmap::FisheyeLens::equidistant180(s.width, s.height);
      s.equidistant180 = true;
    } else {  // a file written by `penumbra calibrate-fisheye`
      s.lensFile = (dir / name).string();
      if (!std::filesystem::exists(s.lensFile)) {
        lens.fail("\"" + name + "\": no such lens file (" + s.lensFile +
                  R"(); expected "equidistant180", a file written by `penumbra calibrate-fisheye` )"
                  R"(or {"fx", "fy", "cx", "cy", "k": [k1, k2, k3, k4]})");
      }
      try {
        s.lens = envmap::readFisheyeLensFile(s.lensFile, core::throwAs<ConfigError>).lens;
      } catch (const core::Error& error) {
        lens.fail(error.what());
      }
      if (s.lens.width != s.width || s.lens.height != s.height) {
        lens.fail(s.lensFile + ": calibrated for " + std::to_string(s.lens.width) + "x" +
                  std::to_string(s.lens.height) + " images, the environment camera's are " +
                  std::to_string(s.width) + "x" + std::to_string(s.height));
      }
      s.equidistant180 = false;
    }
  } else {
    lens.object({"fx", "fy", "cx", "cy", "k"});
    s.lens.width = s.width;
    s.lens.height = s.height;
    s.lens.fx = lens["fx"].number(1e-3, 1e6);
    s.lens.fy = lens["fy"].number(1e-3, 1e6);
    s.lens.cx = lens["cx"].number(0, s.width);
    s.lens.cy = lens["cy"].number(0, s.height);
    const std::vector<double> k = lens["k"].numbers(4);
    for (size_t i = 0; i < 4; ++i) {
      if (!(std::abs(k[i]) <= 100)) {
        // Appended, not "k" + std::string: GCC 12 at -O3 for aarch64 warns (-Wrestrict,
        // a false positive, GCC bug 105329) on a literal + temporary string here.
        lens["k"].fail(
            std::string("k").append(std::to_string(i + 1)).append(" must be in [-100, 100]"));
      }
      s.lens.k[i] = k[i];
    }
    s.equidistant180 = false;
  }
  // The hemisphere map needs every direction up to 90° from the axis (Havran et al. 2005
  // §5.1); a lens that sees less would leave the map's rim unseen (the resampler refuses it
  // at start, with a sample index): refused here, by its reach, where the site edits it.
  s.lensReach = envmap::nearestEdgeReach(s.lens);
  if (!envmap::reachesHemisphere(s.lensReach)) {
    char reach[32];
    std::snprintf(reach, sizeof reach, "%.2f", s.lensReach * 180 / std::numbers::pi);
    lens.fail((s.lensFile.empty() ? std::string("the lens") : s.lensFile) + " sees " + reach +
              " deg from its axis towards the nearest image edge: the hemisphere map needs 90 "
              "deg (a wider lens, or the lens centred in the image)");
  }
  if (const auto r = e.find("response")) {
    if (!r->json().is_string() && !r->json().is_number()) {
      r->fail(R"(expected "srgb", a gamma (a number in [1, 4]) or a response file)");
    }
    if (r->json().is_string()) {
      const std::string name = r->nonEmptyString();
      if (name != "srgb") {  // a file written by `penumbra camera-response`
        s.responseFile = (dir / name).string();
        if (!std::filesystem::exists(s.responseFile)) {
          r->fail("\"" + name + "\": no such response file (" + s.responseFile +
                  "); expected \"srgb\", a gamma (a number in [1, 4]) or a file written by "
                  "`penumbra camera-response`");
        }
        try {
          s.response = readCameraResponse(s.responseFile, core::throwAs<ConfigError>);
        } catch (const core::Error& error) {
          r->fail(error.what());
        }
      }
    } else {
      s.gamma = r->number(1.0, 4.0);
    }
  }
  s.exposureScale = e.numberOr("exposure_scale", 1.0, 1e-6, 1e6);
  readBracket(e, s);
  readLiveLightOptions(e, o);
  return s;
}

}  // namespace penumbra::kiosk
