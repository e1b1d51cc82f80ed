#include "firmware-sim/session.h"

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

namespace penumbra::firmware_sim {
namespace {

using nlohmann::json;

// A JSON object read field by field; refuses keys it was never asked for.
class Fields {
 public:
  Fields(const json& j, std::string where, const std::string& file)
      : j_(j), where_(std::move(where)), file_(file) {
    if (!j_.is_object()) fail("", "must be an object");
  }

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    std::string field = where_;
    if (!key.empty()) field += (field.empty() ? "" : ".") + key;
    throw SessionError(file_ + ": " + (field.empty() ? "" : field + ": ") + what);
  }

  const json* find(const std::string& key) {
    seen_.insert(key);
    const auto it = j_.find(key);
    return it == j_.end() ? nullptr : &*it;
  }
  const json& need(const std::string& key) {
    const json* v = find(key);
    if (!v) fail(key, "is required");
    return *v;
  }

  int64_t integer(const std::string& key, int64_t lo, int64_t hi, int64_t fallback,
                  bool required = false) {
    const json* v = required ? &need(key) : find(key);
    if (!v) return fallback;
    if (!v->is_number_integer()) fail(key, "must be an integer");
    const int64_t x = v->get<int64_t>();
    if (x < lo || x > hi) {
      fail(key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (got " +
                    std::to_string(x) + ")");
    }
    return x;
  }
  double number(const std::string& key, double lo, double hi, double fallback) {
    const json* v = find(key);
    if (!v) return fallback;
    if (!v->is_number()) fail(key, "must be a number");
    const double x = v->get<double>();
    if (!(x >= lo && x <= hi)) {
      std::ostringstream s;
      s << "must be in [" << lo << ", " << hi << "] (got " << x << ")";
      fail(key, s.str());
    }
    return x;
  }
  bool boolean(const std::string& key, bool fallback) {
    const json* v = find(key);
    if (!v) return fallback;
    if (!v->is_boolean()) fail(key, "must be true or false");
    return v->get<bool>();
  }
  std::string string(const std::string& key, const std::string& fallback, bool required = false) {
    const json* v = required ? &need(key) : find(key);
    if (!v) return fallback;
    if (!v->is_string()) fail(key, "must be a string");
    return v->get<std::string>();
  }
  Fields object(const std::string& key) {
    static const json kEmpty = json::object();
    const json* v = find(key);
    return Fields(v ? *v : kEmpty, where_.empty() ? key : where_ + "." + key, file_);
  }
  // Each element of an array of objects.
  template <class F>
  void each(const std::string& key, F&& f) {
    const json* v = find(key);
    if (!v) return;
    if (!v->is_array()) fail(key, "must be an array");
    for (size_t i = 0; i < v->size(); ++i) {
      Fields e((*v)[i], (where_.empty() ? "" : where_ + ".") + key + "[" + std::to_string(i) + "]",
               file_);
      f(e);
      e.done();
    }
  }
  void done() const {
    for (const auto& [k, v] : j_.items()) {
      if (!seen_.count(k) && k.rfind("_comment", 0) != 0) fail(k, "unknown key");
    }
  }

 private:
  const json& j_;
  std::string where_;
  const std::string& file_;
  std::set<std::string> seen_;
};

constexpr int64_t kMs = 1'000'000;
constexpr int64_t kHour = 3'600'000;  // ms

}  // namespace

Session loadSession(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream in(path);
  if (!in) throw SessionError(file + ": cannot open");
  json doc;
  try {
    doc = json::parse(in);
  } catch (const json::parse_error& e) {
    throw SessionError(file + ": not valid JSON (" + e.what() + ")");
  }
  Session s;
  s.file = path;
  Fields root(doc, "", file);
  if (root.string("format", "", true) != "penumbra-session") {
    root.fail("format", "must be \"penumbra-session\"");
  }
  root.integer("version", 1, 1, 1, true);
  const std::filesystem::path dir = path.parent_path();
  const std::string bundle = root.string("bundle", "", true);
  if (bundle.empty()) root.fail("bundle", "must name a bundle file");
  s.bundle = dir / bundle;
  const std::string lastGood = root.string("last_good_bundle", "");
  if (!lastGood.empty()) s.lastGood = dir / lastGood;
  s.frames = static_cast<uint32_t>(root.integer("frames", 1, 1'000'000, 600));

  {
    Fields k = root.object("kiosk");
    kiosk::KioskOptions& o = s.kiosk;
    const int64_t fps = k.integer("fps", 1, 240, 30);
    const int64_t qfps = k.integer("quality_fps", 1, 240, 15);
    o.fastFrameNs = 1'000'000'000 / fps;
    o.qualityFrameNs = 1'000'000'000 / qfps;
    o.fixedCostNs = k.integer("fixed_cost_us", 0, 10'000'000, 0) * 1000;
    if (o.fixedCostNs >= o.fastFrameNs || o.fixedCostNs >= o.qualityFrameNs) {
      k.fail("fixed_cost_us", "must be below the frame time of both modes");
    }
    o.minPasses = static_cast<uint32_t>(k.integer("min_passes", 1, 256, 4));
    o.maxPasses = static_cast<uint32_t>(k.integer("max_passes", 1, 256, 64));
    if (o.minPasses > o.maxPasses) k.fail("min_passes", "must be <= max_passes");
    o.initialPasses = static_cast<uint32_t>(k.integer("initial_passes", 0, 256, 8));
    if (o.initialPasses != 0 && (o.initialPasses < o.minPasses || o.initialPasses > o.maxPasses)) {
      k.fail("initial_passes", "must be 0 or in [min_passes, max_passes]");
    }
    o.attractAfterNs = k.integer("attract_after_ms", 1, kHour, 20'000) * kMs;
    o.attractMilliDegreesPerSecond =
        static_cast<uint32_t>(k.integer("attract_mdeg_per_s", 0, 3'600'000, 12'000));
    o.moveStepMetres = static_cast<float>(k.number("move_step_m", 0.001, 2.0, 0.1));
    o.rotateStepDegrees = static_cast<float>(k.number("rotate_step_deg", 0.1, 180.0, 15.0));
    o.staleAfterNs = k.integer("stale_after_ms", 1, 60'000, 100) * kMs;
    o.reopenEveryNs = k.integer("reopen_every_ms", 1, 60'000, 1000) * kMs;
    o.debounce.settleNs = k.integer("debounce_ms", 0, 1000, 20) * kMs;
    o.debounce.stuckNs = k.integer("stuck_after_ms", 1, kHour, 5000) * kMs;
    if (o.debounce.stuckNs <= o.debounce.settleNs) {
      k.fail("stuck_after_ms", "must be longer than debounce_ms");
    }
    o.hud = k.boolean("hud", true);
    k.done();
  }
  {
    Fields b = root.object("board");
    s.cost.fixedNs = b.integer("fixed_us", 0, 10'000'000, 6'000) * 1000;
    s.cost.perPassNs = b.integer("per_pass_us", 0, 10'000'000, 500) * 1000;
    s.cost.perTexelPs = b.integer("per_texel_ps", 0, 1'000'000, 0);
    s.cost.perPixelPs = b.integer("per_pixel_ps", 0, 1'000'000'000, 0);
    b.each("load_steps", [&](Fields& e) {
      const int64_t at = e.integer("at_ms", 0, kHour, 0, true) * kMs;
      if (!s.loadSteps.empty() && at <= s.loadSteps.back().atNs) {
        e.fail("at_ms", "load steps must be in increasing time");
      }
      s.loadSteps.push_back(
          {at, static_cast<uint32_t>(e.integer("permille", 1, 100'000, 0, true))});
    });
    b.each("overruns", [&](Fields& e) {
      s.overruns.push_back({static_cast<uint32_t>(e.integer("frame", 1, 1'000'000, 0, true)),
                            e.integer("extra_ms", 1, 60'000, 0, true) * kMs});
    });
    b.done();
  }
  {
    Fields c = root.object("camera");
    s.cameraPresent = c.boolean("present", true);
    const std::string source = c.string("source", "");
    if (!source.empty()) s.cameraSource = dir / source;
    CameraScript& cs = s.camera;
    cs.periodNs = 1'000'000'000 / c.integer("fps", 1, 240, 30);
    cs.transportNs = c.integer("transport_us", 0, 1'000'000, 8'000) * 1000;
    {
      Fields d = c.object("drift");
      cs.driftPermille = static_cast<uint32_t>(d.integer("permille", 0, 900, 0));
      cs.driftPeriodFrames = static_cast<uint32_t>(d.integer("period_frames", 0, 1'000'000, 0));
      d.done();
    }
    {
      Fields p = c.object("person");
      cs.personFrom = static_cast<uint64_t>(p.integer("from_frame", 0, 10'000'000, 0));
      cs.personTo = static_cast<uint64_t>(p.integer("to_frame", 0, 10'000'000, 0));
      if (cs.personTo != 0 && cs.personTo <= cs.personFrom) {
        p.fail("to_frame", "must be after from_frame");
      }
      cs.personWidth = static_cast<uint32_t>(p.integer("width_px", 4, 4096, 60));
      cs.personHeight = static_cast<uint32_t>(p.integer("height_px", 4, 4096, 300));
      p.done();
    }
    c.each("faults", [&](Fields& e) {
      CameraFault f{};
      const std::string kind = e.string("kind", "", true);
      bool known = false;
      for (CameraFaultKind k : {CameraFaultKind::kDrop, CameraFaultKind::kLate,
                                CameraFaultKind::kDuplicate, CameraFaultKind::kWrongSize,
                                CameraFaultKind::kWrongFormat, CameraFaultKind::kDisconnect}) {
        if (kind == cameraFaultName(k)) f.kind = k, known = true;
      }
      if (!known) {
        e.fail("kind", "unknown fault '" + kind +
                           "' (drop, late, duplicate, wrong_size, wrong_format, disconnect)");
      }
      f.frame = static_cast<uint64_t>(e.integer("frame", 0, 10'000'000, 0, true));
      f.count = static_cast<uint64_t>(e.integer("count", 1, 10'000'000, 1));
      f.delayNs = e.integer("delay_ms", 0, 60'000, 0, f.kind == CameraFaultKind::kLate) * kMs;
      if (f.kind == CameraFaultKind::kLate && f.delayNs == 0) e.fail("delay_ms", "must be > 0");
      cs.faults.push_back(f);
    });
    c.done();
  }
  {
    Fields g = root.object("gpio");
    const std::string chip = g.string("chip", "present");
    if (chip != "present" && chip != "missing")
      g.fail("chip", "must be \"present\" or \"missing\"");
    s.gpioPresent = chip == "present";
    g.each("presses", [&](Fields& e) {
      ScriptedPress p;
      p.atNs = e.integer("at_ms", 0, kHour, 0, true) * kMs;
      const std::string name = e.string("button", "", true);
      const auto b = kiosk::parseButton(name);
      if (!b) {
        e.fail("button", "unknown button '" + name +
                             "' (next, previous, left, right, forward, back, rotate, quality)");
      }
      p.button = *b;
      p.holdNs = e.integer("hold_ms", 1, kHour, 80) * kMs;
      p.bounces = static_cast<uint32_t>(e.integer("bounces", 0, 100, 0));
      p.bounceNs = e.integer("bounce_us", 1, 100'000, 1000) * 1000;
      if (2 * static_cast<int64_t>(p.bounces) * p.bounceNs >= p.holdNs) {
        e.fail("bounces", "bouncing must end before the release (hold_ms)");
      }
      s.presses.push_back(p);
    });
    g.done();
  }
  {
    Fields u = root.object("startup");
    s.corruptBundle = u.boolean("corrupt_bundle", false);
    s.corruptProduct = u.string("corrupt_product", "");
    u.done();
  }
  root.each("product_files", [&](Fields& e) {
    ScriptedProductFile f;
    f.atNs = e.integer("at_ms", 0, kHour, 0) * kMs;
    if (!s.productFiles.empty() && f.atNs < s.productFiles.back().atNs) {
      e.fail("at_ms", "product files must be in time order");
    }
    f.product = e.string("product", "", true);
    const std::string model = e.string("file", "", true);
    if (model.empty()) e.fail("file", "must name a model file");
    f.file = dir / model;
    s.productFiles.push_back(std::move(f));
  });
  root.done();
  return s;
}

}  // namespace penumbra::firmware_sim
