#include "firmware-sim/session.h"

#include <string_view>
#include <vector>

#include "core/json_reader.h"
#include "core/regular_file.h"
#include "kiosk/kiosk_config.h"
#include "scene/bundle_io.h"

namespace penumbra::firmware_sim {
namespace {

using core::JsonValue;

constexpr int64_t kHour = 3'600'000;  // ms

// "board": the simulated board's cost model, its load steps and overrun frames.
void readBoard(const JsonValue& b, Session& s) {
  s.cost.fixedNs = b.integerOr("fixed_us", 6'000, 0, 10'000'000) * 1000;
  s.cost.perPassNs = b.integerOr("per_pass_us", 500, 0, 10'000'000) * 1000;
  s.cost.perTexelPs = b.integerOr("per_texel_ps", 0, 0, 1'000'000);
  s.cost.perPixelPs = b.integerOr("per_pixel_ps", 0, 0, 1'000'000'000);
  s.cost.perPassVertexPs = b.integerOr("per_pass_vertex_ps", 0, 0, 1'000'000'000);
  s.cost.perProductVertexPs = b.integerOr("per_product_vertex_ps", 0, 0, 1'000'000'000);
  s.cost.perShadedVertexPs = b.integerOr("per_shaded_vertex_ps", 0, 0, 1'000'000'000);
  s.cost.perTransferredVertexPs = b.integerOr("per_transferred_vertex_ps", 0, 0, 1'000'000'000);
  s.cost.perPassTransferredVertexPs =
      b.integerOr("per_pass_transferred_vertex_ps", 0, 0, 1'000'000'000);
  s.cost.perShadowMapTrianglePs = b.integerOr("per_shadow_map_triangle_ps", 0, 0, 1'000'000'000);
  for (const JsonValue& e : b.optionalArray("load_steps")) {
    e.object({"at_ms", "permille"});
    const int64_t at = e["at_ms"].integer(0, kHour) * kNsPerMs;
    if (!s.loadSteps.empty() && at <= s.loadSteps.back().atNs) {
      e["at_ms"].fail("load steps must be in increasing time");
    }
    s.loadSteps.push_back({at, static_cast<uint32_t>(e["permille"].integer(1, 100'000))});
  }
  for (const JsonValue& e : b.optionalArray("overruns")) {
    e.object({"frame", "extra_ms"});
    s.overruns.push_back({static_cast<uint32_t>(e["frame"].integer(1, 1'000'000)),
                          e["extra_ms"].integer(1, 60'000) * kNsPerMs});
  }
}

CameraFault readCameraFault(const JsonValue& e) {
  e.object({"kind", "frame", "count", "delay_ms"});
  static constexpr CameraFaultKind kKinds[] = {
      CameraFaultKind::kDrop,      CameraFaultKind::kLate,        CameraFaultKind::kDuplicate,
      CameraFaultKind::kWrongSize, CameraFaultKind::kWrongFormat, CameraFaultKind::kDisconnect};
  std::vector<std::string_view> names;
  for (CameraFaultKind k : kKinds) names.push_back(cameraFaultName(k));
  CameraFault f{};
  f.kind = kKinds[e["kind"].oneOf(names)];
  f.frame = static_cast<uint64_t>(e["frame"].integer(0, 10'000'000));
  f.count = static_cast<uint64_t>(e.integerOr("count", 1, 1, 10'000'000));
  // A late frame needs its delay; the other faults may leave it out.
  f.delayNs = (f.kind == CameraFaultKind::kLate ? e["delay_ms"].integer(0, 60'000)
                                                : e.integerOr("delay_ms", 0, 0, 60'000)) *
              kNsPerMs;
  if (f.kind == CameraFaultKind::kLate && f.delayNs == 0) e["delay_ms"].fail("must be > 0");
  return f;
}

// "camera": the simulated camera's footage, timing, drift, the person walking by, faults.
void readCamera(const JsonValue& c, const std::filesystem::path& dir, Session& s) {
  s.cameraPresent = c.booleanOr("present", true);
  const std::string source = c.stringOr("source", "");
  if (!source.empty()) s.cameraSource = dir / source;
  CameraScript& cs = s.camera;
  cs.periodNs = 1'000'000'000 / c.integerOr("fps", 30, 1, 240);
  cs.transportNs = c.integerOr("transport_us", 8'000, 0, 1'000'000) * 1000;
  const JsonValue d = c.optionalObject("drift", {"permille", "period_frames"});
  cs.driftPermille = static_cast<uint32_t>(d.integerOr("permille", 0, 0, 900));
  cs.driftPeriodFrames = static_cast<uint32_t>(d.integerOr("period_frames", 0, 0, 1'000'000));
  const JsonValue p =
      c.optionalObject("person", {"from_frame", "to_frame", "width_px", "height_px"});
  cs.personFrom = static_cast<uint64_t>(p.integerOr("from_frame", 0, 0, 10'000'000));
  cs.personTo = static_cast<uint64_t>(p.integerOr("to_frame", 0, 0, 10'000'000));
  if (cs.personTo != 0 && cs.personTo <= cs.personFrom) {
    p["to_frame"].fail("must be after from_frame");
  }
  cs.personWidth = static_cast<uint32_t>(p.integerOr("width_px", 60, 4, 4096));
  cs.personHeight = static_cast<uint32_t>(p.integerOr("height_px", 300, 4, 4096));
  for (const JsonValue& e : c.optionalArray("faults")) cs.faults.push_back(readCameraFault(e));
}

ScriptedPress readPress(const JsonValue& e) {
  e.object({"at_ms", "button", "hold_ms", "bounces", "bounce_us"});
  ScriptedPress p;
  p.atNs = e["at_ms"].integer(0, kHour) * kNsPerMs;
  const std::string name = e["button"].string();
  const auto b = kiosk::parseButton(name);
  if (!b) {
    e["button"].fail("unknown button '" + name +
                     "' (next, previous, left, right, forward, back, rotate, quality)");
  }
  p.button = *b;
  p.holdNs = e.integerOr("hold_ms", 80, 1, kHour) * kNsPerMs;
  p.bounces = static_cast<uint32_t>(e.integerOr("bounces", 0, 0, 100));
  p.bounceNs = e.integerOr("bounce_us", 1000, 1, 100'000) * 1000;
  if (2 * static_cast<int64_t>(p.bounces) * p.bounceNs >= p.holdNs) {
    e["bounces"].fail("bouncing must end before the release (hold_ms)");
  }
  return p;
}

// "gpio": whether the chip is there, and the scripted button presses.
void readGpio(const JsonValue& g, Session& s) {
  s.gpioPresent = !g.has("chip") || g["chip"].oneOf({"present", "missing"}) == 0;
  for (const JsonValue& e : g.optionalArray("presses")) s.presses.push_back(readPress(e));
}

// "product_files": model files that appear on the board's storage while it runs.
void readProductFiles(const JsonValue& root, const std::filesystem::path& dir, Session& s) {
  for (const JsonValue& e : root.optionalArray("product_files")) {
    e.object({"at_ms", "product", "file"});
    ScriptedProductFile f;
    f.atNs = e.integerOr("at_ms", 0, 0, kHour) * kNsPerMs;
    if (!s.productFiles.empty() && f.atNs < s.productFiles.back().atNs) {
      e["at_ms"].fail("product files must be in time order");
    }
    f.product = e["product"].string();
    const std::string model = e["file"].string();
    if (model.empty()) e["file"].fail("must name a model file");
    f.file = dir / model;
    s.productFiles.push_back(std::move(f));
  }
}

// "environment": the simulated environment camera and the live lights' options.
void readEnvironment(const JsonValue& root, const std::filesystem::path& dir, Session& s) {
  if (!root.has("environment")) return;
  const JsonValue e =
      root["environment"].object({"frames", "fps", "stop_at_ms", "samples", "lights", "yaw_deg",
                                  "radiance_scale", "stale_after_ms"});
  EnvironmentScript env;
  const std::string frames = e["frames"].string();
  if (frames.empty()) e["frames"].fail("must name a folder of fisheye EXR frames");
  env.frames = dir / frames;
  env.periodNs = 1'000'000'000 / e.integerOr("fps", 21, 1, 240);
  env.stopAtNs = e.has("stop_at_ms") ? e["stop_at_ms"].integer(0, kHour) * kNsPerMs : -1;
  kiosk::readLiveLightOptions(e, s.kiosk);
  s.environment = env;
}

}  // namespace

Session loadSession(const std::filesystem::path& path) {
  const core::JsonDocument doc(path, core::throwAs<SessionError>);
  const JsonValue root =
      doc.root().object({"format", "version", "bundle", "last_good_bundle", "frames", "kiosk",
                         "board", "camera", "gpio", "startup", "product_files", "environment"});
  Session s;
  s.file = path;
  if (root["format"].string() != "penumbra-session") {
    root["format"].fail("must be \"penumbra-session\"");
  }
  root["version"].integer(1, 1);
  const std::filesystem::path dir = path.parent_path();
  const std::string bundle = root["bundle"].string();
  if (bundle.empty()) root["bundle"].fail("must name a bundle file");
  s.bundle = dir / bundle;
  // Refused here, naming the session, rather than by the bundle reader (sim_run.cpp).
  core::requireRegularFile(s.bundle, scene::kMaxBundleBytes, "a scene bundle",
                           core::throwAs<SessionError>, path.string() + ": bundle: ");
  const std::string lastGood = root.stringOr("last_good_bundle", "");
  if (!lastGood.empty()) s.lastGood = dir / lastGood;
  s.frames = static_cast<uint32_t>(root.integerOr("frames", 600, 1, 1'000'000));

  s.kiosk = kiosk::readLoopOptions(root, "kiosk", kiosk::HudMode::kOn);
  readBoard(root.optionalObject(
                "board", {"fixed_us", "per_pass_us", "per_texel_ps", "per_pixel_ps",
                          "per_pass_vertex_ps", "per_product_vertex_ps", "per_shaded_vertex_ps",
                          "per_transferred_vertex_ps", "per_pass_transferred_vertex_ps",
                          "per_shadow_map_triangle_ps", "load_steps", "overruns"}),
            s);
  readCamera(root.optionalObject("camera", {"present", "source", "fps", "transport_us", "drift",
                                            "person", "faults"}),
             dir, s);
  readGpio(root.optionalObject("gpio", {"chip", "presses"}), s);
  const JsonValue u = root.optionalObject("startup", {"corrupt_bundle", "corrupt_product"});
  s.corruptBundle = u.booleanOr("corrupt_bundle", false);
  s.corruptProduct = u.stringOr("corrupt_product", "");
  readProductFiles(root, dir, s);
  readEnvironment(root, dir, s);
  return s;
}

}  // namespace penumbra::firmware_sim
