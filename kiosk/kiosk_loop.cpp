#include "kiosk/kiosk_loop.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <thread>

#include "scene/portable_trig.h"
#include "shadow/frame_loop.h"
#include "shadow/render_settings.h"

namespace penumbra::kiosk {

void SteadyTimebase::sleepUntil(int64_t ns) {
  const int64_t now = nowNanoseconds();
  if (ns > now) std::this_thread::sleep_for(std::chrono::nanoseconds(ns - now));
}

namespace {

// A fine proxy is drawn by its product's fine-proxy passes (RenderSettings; 16 of 50 by
// default, up to every pass): at this limit twice the largest proxy accepted below, so a frame
// that draws it in every pass costs at most twice one of the largest proxies.
constexpr size_t kMaxFineProxyTriangles = 10000;

bool meshUsable(const core::Mesh& m, std::string& why) {
  if (m.positions.empty() || m.indices.empty() || m.indices.size() % 3 != 0) {
    why = "empty or not triangles";
    return false;
  }
  for (uint32_t i : m.indices) {
    if (i >= m.positions.size()) {
      why = "index " + std::to_string(i) + " past " + std::to_string(m.positions.size()) +
            " vertices";
      return false;
    }
  }
  for (const core::Vec3& p : m.positions) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      why = "a vertex is not a finite number";
      return false;
    }
  }
  return true;
}

std::string seconds(int64_t ns) {
  const int64_t tenths = ns / 100'000'000;
  return std::to_string(tenths / 10) + "." + std::to_string(tenths % 10) + " S";
}

}  // namespace

std::vector<uint32_t> validateProducts(const shadow::SceneBundle& bundle,
                                       std::vector<std::string>& why) {
  std::vector<uint32_t> usable;
  for (uint32_t i = 0; i < bundle.products.size(); ++i) {
    const shadow::ProductModel& p = bundle.products[i];
    std::string reason;
    // (Built with append: GCC 12's -Wrestrict misfires on "literal" + std::string here.)
    std::string name = "product ";
    if (p.name.empty()) {
      name.append("#").append(std::to_string(i));
    } else {
      name.append(p.name);
    }
    name.append(": ");
    if (!meshUsable(p.mesh, reason)) {
      why.push_back(name.append("mesh ").append(reason));
    } else if (!meshUsable(p.proxy, reason)) {
      why.push_back(name.append("shadow proxy ").append(reason));
    } else if (p.proxy.triangleCount() > 5000) {
      why.push_back(name.append("shadow proxy has ")
                        .append(std::to_string(p.proxy.triangleCount()))
                        .append(" triangles (Gibson 2003 §7.2 uses 100-500)"));
    } else if (!p.fineProxy.indices.empty() && !meshUsable(p.fineProxy, reason)) {
      why.push_back(name.append("fine shadow proxy ").append(reason));
    } else if (p.fineProxy.triangleCount() > kMaxFineProxyTriangles) {
      why.push_back(name.append("fine shadow proxy has ")
                        .append(std::to_string(p.fineProxy.triangleCount()))
                        .append(" triangles (at most ")
                        .append(std::to_string(kMaxFineProxyTriangles))
                        .append(")"));
    } else {
      usable.push_back(i);
    }
  }
  return usable;
}

struct KioskLoop::State {
  State(const shadow::SceneBundle& b, const KioskOptions& o, const raster::RenderOptions& r)
      : debouncer(o.debounce),
        loop(b, shadow::compositorOptions(b.settings), r),
        background(b.background),
        foreground(b.background, b.view.width, b.view.height, o.foreground) {}

  Debouncer debouncer;
  std::unique_ptr<shadow::FrameRateController> controller;
  std::unique_ptr<shadow::FootprintDetail> detail;  // beside the controller, the same ceiling
  std::vector<shadow::YawSphere> spheres;           // per product (footprint_detail.h)
  shadow::FrameLoop loop;  // compose, render, observe; its rgba is the frame shown
  std::vector<RawEdge> edges;
  std::vector<ButtonAction> actions;
  std::vector<Debouncer::StuckChange> stuck;

  shadow::ProductPose pose;
  size_t carouselIndex = 0;
  bool quality = false;
  bool attract = false;
  int64_t attractStartNs = 0;
  size_t attractFirstProduct = 0;
  int64_t lastInputNs = 0;
  bool serviceHud = false;   // HudMode::kService: shown now
  bool serviceHeld = false;  // the current hold has toggled it already

  // Camera.
  CameraFrame grabbed;
  std::vector<uint8_t> background;  // the last good camera frame, or the bundle's photograph
  std::vector<uint8_t> converted;
  ForegroundMask foreground;  // against the bundle's photograph, the empty room
  uint64_t backgroundSequence = 0;
  int64_t backgroundCaptureNs = -1;  // -1: no camera frame yet
  bool haveSequence = false;
  uint64_t lastSequence = 0;
  bool disconnected = false;
  int64_t disconnectedAtNs = 0;
  int64_t nextReopenNs = 0;
  int64_t lastBadFrameNs = INT64_MIN;
  bool staleSaid = false;
  int64_t staleSinceNs = 0;
  bool frameNew = false;

  // Live lighting (io.environment).
  std::unique_ptr<envmap::LiveLights> live;
  envmap::HemisphereMap environmentMap;  // the last good one (the HUD's inset shows it)
  envmap::HemisphereMap grabbedMap;
  std::unique_ptr<EnvironmentInset> inset;  // on the HUD, when it is shown
  int64_t environmentFrameNs = -1;          // when the last good environment frame arrived
  bool environmentDisconnected = false, environmentStaleSaid = false, environmentBad = false;

  // Frame bookkeeping.
  std::vector<int64_t> recentStarts;  // the last frames' start times, for the HUD's fps
  LedState led = LedState::kError;
  bool overBudget = false;
  std::map<std::string, std::string> faults;  // setFault(): key → HUD text
  float minX = 0, maxX = 0, minZ = 0, maxZ = 0;
};

KioskLoop::KioskLoop(const shadow::SceneBundle& bundle, const KioskOptions& options,
                     const Peripherals& io, const raster::RenderOptions& render)
    : bundle_(bundle), options_(options), io_(io) {
  if (io_.led == nullptr || io_.time == nullptr || io_.log == nullptr) {
    throw std::invalid_argument("KioskLoop: the LED, the timebase and the log are required");
  }
  std::vector<std::string> why;
  carousel_ = validateProducts(bundle, why);
  const int64_t now = io_.time->nowNanoseconds();
  for (const std::string& w : why) warn(now, "refused " + w + " (left out of the carousel)");
  if (carousel_.empty()) {
    io_.led->set(LedState::kError);
    throw std::invalid_argument("KioskLoop: the bundle has no usable product");
  }
  s_ = std::make_unique<State>(bundle, options_, render);
  if (io_.environment != nullptr) {
    s_->live = std::make_unique<envmap::LiveLights>(options_.liveLights);
  }

  // The floor's extent from the room's own triangles (the patch mesh spans the shell).
  const auto& pos = bundle.view.staticMesh.positions;
  s_->minX = s_->minZ = INFINITY;
  s_->maxX = s_->maxZ = -INFINITY;
  for (const core::Vec3& p : pos) {
    s_->minX = std::min(s_->minX, p.x), s_->maxX = std::max(s_->maxX, p.x);
    s_->minZ = std::min(s_->minZ, p.z), s_->maxZ = std::max(s_->maxZ, p.z);
  }
  const float m = options_.floorMarginMetres;
  s_->minX += m, s_->maxX -= m, s_->minZ += m, s_->maxZ -= m;
  if (!(s_->minX <= s_->maxX && s_->minZ <= s_->maxZ)) {
    throw std::invalid_argument("KioskLoop: the floor is smaller than twice the margin");
  }

  s_->pose = bundle.startPose;
  auto start = std::find(carousel_.begin(), carousel_.end(), s_->pose.product);
  if (start == carousel_.end()) {
    s_->pose.product = carousel_[0];
    start = carousel_.begin();
  }
  s_->carouselIndex = static_cast<size_t>(start - carousel_.begin());
  s_->lastInputNs = now;
  for (const shadow::ProductModel& p : bundle.products) {
    s_->spheres.push_back(shadow::yawSphere(p.mesh));
  }
  rebuildController();

  info(now, "kiosk: " + std::to_string(carousel_.size()) + " products, " +
                std::to_string(bundle.view.width) + "x" + std::to_string(bundle.view.height));
  info(now, io_.camera ? "camera: " + io_.camera->describe()
                       : "camera: none configured; showing the calibration photograph");
  if (io_.environment) {
    info(now, "live lighting: " + io_.environment->describe() + ", " +
                  std::to_string(options_.liveLights.samples) + " samples, at most " +
                  std::to_string(options_.liveLights.maxLights) + " lights");
  }
  if (io_.buttons) {
    info(now, "buttons: " + io_.buttons->describe());
  } else {
    warn(now, "buttons: none (no GPIO chip?); running attract mode only");
  }
}

KioskLoop::~KioskLoop() = default;

void KioskLoop::info(int64_t now, const std::string& text) {
  io_.log->write(now, LogLevel::kInfo, text);
}
void KioskLoop::warn(int64_t now, const std::string& text) {
  io_.log->write(now, LogLevel::kWarning, text);
}

void KioskLoop::rebuildController() {
  shadow::FrameRateController::Options o;
  o.targetFrameNs = s_->quality ? options_.qualityFrameNs : options_.fastFrameNs;
  o.fixedCostNs = options_.fixedCostNs;
  // A bundle tuned to fewer passes than the kiosk allows caps them; the floor and the
  // start follow the cap down.
  o.maxPasses = std::min(options_.maxPasses, bundle_.settings.maxPasses);
  o.minPasses = std::min(options_.minPasses, o.maxPasses);
  o.initialPasses = std::min(options_.initialPasses, o.maxPasses);
  o.shadowMapSizes = shadow::shadowMapLadder(bundle_.settings);
  shadow::FootprintDetailOptions detail = options_.footprintDetail;
  detail.minPasses = o.minPasses;  // the controller's floor
  s_->detail = std::make_unique<shadow::FootprintDetail>(detail, o.maxPasses, o.shadowMapSizes);
  s_->controller = std::make_unique<shadow::FrameRateController>(o);
}

void KioskLoop::apply(const ButtonAction& a) {
  shadow::ProductPose& p = s_->pose;
  const float step = options_.moveStepMetres;
  switch (a.button) {
    case Button::kNext:
    case Button::kPrevious: {
      const size_t n = carousel_.size();
      s_->carouselIndex =
          a.button == Button::kNext ? (s_->carouselIndex + 1) % n : (s_->carouselIndex + n - 1) % n;
      p.product = carousel_[s_->carouselIndex];
      info(a.timeNs, "product: " + bundle_.products[p.product].name);
      break;
    }
    case Button::kLeft:
      p.x = std::max(s_->minX, p.x - step);
      break;
    case Button::kRight:
      p.x = std::min(s_->maxX, p.x + step);
      break;
    case Button::kForward:
      p.z = std::min(s_->maxZ, p.z + step);
      break;
    case Button::kBack:
      p.z = std::max(s_->minZ, p.z - step);
      break;
    case Button::kRotate:
      p.yawDegrees += options_.rotateStepDegrees;
      if (p.yawDegrees >= 360.0f) p.yawDegrees -= 360.0f;
      break;
    case Button::kQuality:
      s_->quality = !s_->quality;
      rebuildController();
      info(a.timeNs,
           s_->quality ? "quality mode: more passes at 15 fps" : "fast mode: 30 fps, fewer passes");
      break;
  }
}

void KioskLoop::handleButtons(int64_t now) {
  if (io_.buttons == nullptr) return;
  s_->edges.clear();
  s_->actions.clear();
  s_->stuck.clear();
  io_.buttons->poll(now, s_->edges);
  s_->debouncer.update(s_->edges, now, s_->actions, s_->stuck);
  for (const auto& c : s_->stuck) {
    if (c.stuck) {
      io_.log->write(c.timeNs, LogLevel::kWarning,
                     std::string("button ") + buttonName(c.button) + ": held for over " +
                         seconds(options_.debounce.stuckNs) +
                         ", taken as stuck and ignored until released");
    } else {
      info(c.timeNs, std::string("button ") + buttonName(c.button) + ": released, usable again");
    }
  }
  if (options_.hud == HudMode::kService) serviceHold(now);
  for (const ButtonAction& a : s_->actions) {
    s_->lastInputNs = a.timeNs;
    if (s_->attract) {
      // The first press only wakes the kiosk up; the product stays where attract mode left it.
      s_->attract = false;
      s_->pose = attractPose(a.timeNs);
      info(a.timeNs, "attract mode: off (button " + std::string(buttonName(a.button)) + ")");
      continue;
    }
    apply(a);
  }
}

// HudMode::kService: `next` and `previous` held together long enough toggle the HUD, once
// per hold.
void KioskLoop::serviceHold(int64_t now) {
  State& s = *s_;
  const Debouncer& d = s.debouncer;
  if (!d.isDown(Button::kNext) || !d.isDown(Button::kPrevious)) {
    s.serviceHeld = false;
    return;
  }
  const int64_t since = std::max(d.downSinceNs(Button::kNext), d.downSinceNs(Button::kPrevious));
  if (s.serviceHeld || now - since < options_.serviceHoldNs) return;
  s.serviceHeld = true;
  s.serviceHud = !s.serviceHud;
  info(now, std::string("service HUD: ") + (s.serviceHud ? "on" : "off") +
                " (next + previous held " + seconds(now - since) + ")");
}

shadow::ProductPose KioskLoop::attractPose(int64_t now) const {
  // A slow circle around the middle of the floor, the product turning with it, and the next
  // product every 10 s. Integer time → millidegrees, then the portable sine (design.md §3:
  // no libm in the per-frame path).
  const int64_t elapsedMs = (now - s_->attractStartNs) / 1'000'000;
  const int64_t milli = (elapsedMs * options_.attractMilliDegreesPerSecond / 1000) % 360'000;
  double s = 0, c = 0;
  scene::sinCosDegrees(static_cast<double>(milli) / 1000.0, s, c);
  const float cx = (s_->minX + s_->maxX) * 0.5f, cz = (s_->minZ + s_->maxZ) * 0.5f;
  const float r = std::min(s_->maxX - s_->minX, s_->maxZ - s_->minZ) * 0.35f;
  shadow::ProductPose p;
  p.x = cx + r * static_cast<float>(c);
  p.z = cz + r * static_cast<float>(s);
  p.yawDegrees = static_cast<float>(milli % 360'000) / 1000.0f;
  p.lift = 0;
  const size_t n = carousel_.size();
  p.product = carousel_[(s_->attractFirstProduct + static_cast<size_t>(elapsedMs / 10'000)) % n];
  return p;
}

void KioskLoop::handleCamera(int64_t now) {
  State& s = *s_;
  s.frameNew = false;
  if (io_.camera == nullptr) return;
  if (s.disconnected) {
    if (now < s.nextReopenNs) return;
    if (!io_.camera->reopen(now)) {
      s.nextReopenNs = now + options_.reopenEveryNs;
      return;
    }
    s.disconnected = false;
    info(now, "camera: reconnected after " + seconds(now - s.disconnectedAtNs));
  }
  const GrabStatus st = io_.camera->grab(now, s.grabbed);
  if (st == GrabStatus::kDisconnected) {
    s.disconnected = true;
    s.disconnectedAtNs = now;
    s.nextReopenNs = now + options_.reopenEveryNs;
    io_.log->write(now, LogLevel::kError,
                   "camera: disconnected (" + io_.camera->describe() +
                       "); showing the last frame, trying to reopen every " +
                       seconds(options_.reopenEveryNs));
    return;
  }
  if (st != GrabStatus::kFrame) return;
  if (s.haveSequence && s.grabbed.sequence <= s.lastSequence) {
    // Keyed: a camera stuck repeating a frame says so once per log window, not per frame.
    io_.log->write(now, LogLevel::kWarning,
                   "camera: frame " + std::to_string(s.grabbed.sequence) +
                       " delivered again (already shown), ignored",
                   "camera: frame delivered again");
    return;
  }
  s.haveSequence = true;
  s.lastSequence = s.grabbed.sequence;
  std::string why;
  if (!toRgba(s.grabbed, bundle_.view.width, bundle_.view.height, s.converted, why,
              options_.cameraOrientation)) {
    s.lastBadFrameNs = now;
    io_.log->write(now, LogLevel::kWarning,
                   "camera: frame " + std::to_string(s.grabbed.sequence) + " refused: " + why +
                       "; keeping the last good frame",
                   "camera: frame refused");
    return;
  }
  s.background.swap(s.converted);
  s.backgroundSequence = s.grabbed.sequence;
  s.backgroundCaptureNs = s.grabbed.captureNs;
  s.frameNew = true;
}

// 1. Buttons, and attract mode when nobody has pressed one for a while.
shadow::ProductPose KioskLoop::inputAndPose(int64_t now) {
  State& s = *s_;
  handleButtons(now);
  if (!s.attract && now - s.lastInputNs >= options_.attractAfterNs) {
    s.attract = true;
    s.attractStartNs = now;
    s.attractFirstProduct = s.carouselIndex;
    info(now, "attract mode: on (idle for " + seconds(now - s.lastInputNs) + ")");
  }
  return s.attract ? attractPose(now) : s.pose;
}

// Live lighting: the environment camera's newest map becomes the lights (Havran 2005 §3:
// CDF, Halton samples, FIR); a camera that stops, a map that cannot be used, are said once
// each, and the lights of the last good map stay. Before the first good map: the captured
// sources.
bool KioskLoop::environmentLights(int64_t now) {
  State& s = *s_;
  if (io_.environment == nullptr) return false;
  GrabStatus status = GrabStatus::kNoFrame;
  try {
    status = io_.environment->grab(now, s.grabbedMap);
    if (status == GrabStatus::kFrame) {
      s.live->update(s.grabbedMap, io_.environment->describe());
      std::swap(s.environmentMap, s.grabbedMap);
      s.environmentFrameNs = now;
      if (s.environmentBad || s.environmentStaleSaid || s.environmentDisconnected) {
        info(now, "environment camera: frames again, live lighting resumed");
      }
      s.environmentBad = s.environmentStaleSaid = s.environmentDisconnected = false;
    }
  } catch (const std::exception& e) {
    if (!s.environmentBad) warn(now, std::string("environment frame refused: ") + e.what());
    s.environmentBad = true;
  }
  if (status == GrabStatus::kDisconnected && !s.environmentDisconnected) {
    warn(now, "environment camera lost: " + io_.environment->describe() +
                  (s.live->ready() ? " (the last lights kept)" : " (captured light)"));
    s.environmentDisconnected = true;
  }
  const bool stale =
      s.environmentFrameNs < 0 || now - s.environmentFrameNs > options_.environmentStaleAfterNs;
  if (stale && !s.environmentStaleSaid && !s.environmentDisconnected) {
    warn(now, s.live->ready() ? "environment camera: no new frame, the last lights kept"
                              : "environment camera: no frame yet, captured light");
    s.environmentStaleSaid = true;
  }
  return s.live->ready();
}

// 2. The newest camera frame becomes the background (design §1 step 1); a camera that
// stops sending is said once when it stops and once when it is back.
KioskLoop::CameraStatus KioskLoop::cameraBackground(int64_t now) {
  State& s = *s_;
  handleCamera(now);
  CameraStatus c;
  c.haveFrame = s.backgroundCaptureNs >= 0;
  c.ageNs = c.haveFrame ? now - s.backgroundCaptureNs : -1;
  c.stale = !c.haveFrame || c.ageNs > options_.staleAfterNs;
  if (c.stale && !s.staleSaid) {
    s.staleSaid = true;
    s.staleSinceNs = now;
    warn(now, c.haveFrame ? "camera: no new frame for " + seconds(c.ageNs) +
                                "; the screen shows the last one, frozen"
                          : "camera: no frame yet; the screen shows the calibration photograph");
  } else if (!c.stale && s.staleSaid) {
    s.staleSaid = false;
    info(now, "camera: live again after " + seconds(now - s.staleSinceNs));
  }
  return c;
}

// The controller's verdict (Gibson 2003 §8), logged when it changes.
void KioskLoop::noteBudget(int64_t now, bool overBudget) {
  State& s = *s_;
  if (overBudget == s.overBudget) return;
  s.overBudget = overBudget;
  if (overBudget) {
    warn(now, "frame rate: below target even at " + std::to_string(options_.minPasses) +
                  " passes and the smallest shadow map");
  } else {
    info(now, "frame rate: back within budget");
  }
}

// What the LED and the HUD say.
std::vector<std::string> KioskLoop::warnings(int64_t now, const CameraStatus& camera,
                                             bool overBudget) const {
  const State& s = *s_;
  std::vector<std::string> w;
  if (io_.camera == nullptr) {
    w.push_back("NO CAMERA - CALIBRATION PHOTOGRAPH");
  } else if (s.disconnected) {
    w.push_back("CAMERA LOST - " +
                (camera.haveFrame ? "LAST FRAME " + seconds(camera.ageNs) + " OLD" : "NO FRAME"));
  } else if (camera.stale) {
    w.push_back(camera.haveFrame ? "CAMERA FROZEN - FRAME " + seconds(camera.ageNs) + " OLD"
                                 : "NO CAMERA FRAME YET - PHOTOGRAPH");
  }
  if (s.lastBadFrameNs != INT64_MIN && now - s.lastBadFrameNs <= options_.staleAfterNs) {
    w.push_back("BAD CAMERA FRAME REFUSED");
  }
  if (io_.environment != nullptr) {
    if (!s.live->ready()) {
      w.push_back("NO ENVIRONMENT FRAME - CAPTURED LIGHT");
    } else if (s.environmentDisconnected) {
      w.push_back("ENVIRONMENT CAMERA LOST - LAST LIGHTS");
    } else if (now - s.environmentFrameNs > options_.environmentStaleAfterNs) {
      w.push_back("ENVIRONMENT FROZEN - LAST LIGHTS");
    }
    if (s.environmentBad) w.push_back("BAD ENVIRONMENT FRAME REFUSED");
  }
  if (io_.buttons == nullptr) w.push_back("NO BUTTONS");
  if (s.debouncer.anyStuck()) {
    std::string names;
    for (size_t i = 0; i < kButtonCount; ++i) {
      if (s.debouncer.isStuck(static_cast<Button>(i))) {
        names += std::string(names.empty() ? "" : " ") + buttonName(static_cast<Button>(i));
      }
    }
    w.push_back("BUTTON STUCK: " + names);
  }
  if (overBudget) w.push_back("OVER BUDGET");
  for (const auto& [key, text] : s.faults) w.push_back(text);
  return w;
}

// Ready without warnings, degraded with any; a change is logged with its reasons.
LedState KioskLoop::showLed(int64_t now, const std::vector<std::string>& warnings) {
  State& s = *s_;
  const LedState led = warnings.empty() ? LedState::kReady : LedState::kDegraded;
  if (led != s.led) {
    std::string why;
    for (const std::string& w : warnings) why += (why.empty() ? "" : "; ") + w;
    io_.log->write(
        now, led == LedState::kReady ? LogLevel::kInfo : LogLevel::kWarning,
        std::string("led: ") + ledStateName(led) + (why.empty() ? "" : " (" + why + ")"));
    s.led = led;
  }
  io_.led->set(led);
  return led;
}

// The HUD's fps over the last 30 frames (integer, from the kiosk clock).
uint32_t KioskLoop::fpsTenths(int64_t now) {
  State& s = *s_;
  s.recentStarts.push_back(now);
  if (s.recentStarts.size() > 31) s.recentStarts.erase(s.recentStarts.begin());
  if (s.recentStarts.size() < 2 || s.recentStarts.back() <= s.recentStarts.front()) return 0;
  return static_cast<uint32_t>(static_cast<int64_t>(s.recentStarts.size() - 1) * 10'000'000'000 /
                               (s.recentStarts.back() - s.recentStarts.front()));
}

FrameReport KioskLoop::step() {
  State& s = *s_;
  const int64_t start = io_.time->nowNanoseconds();
  FrameReport r;
  r.startNs = start;
  // Stage times on the steady clock (measurement only: the controller hears the Timebase).
  using shadow::FrameStage;
  core::Stopwatch watch;
  int64_t other = 0;

  const shadow::ProductPose pose = inputAndPose(start);
  other += watch.lapNs();
  const CameraStatus camera = cameraBackground(start);
  const int64_t cameraNs = watch.lapNs();

  // 3-7. Frame-rate control (Gibson 2003 §8), composition and rendering.
  // The controller spends the frame's time; the product's footprint caps what it may spend
  // on a shadow too small to show it. The controller hears the passes actually drawn, and a
  // map the footprint made smaller reads to it as a lighter load.
  shadow::FrameRateController::Decision d = s.controller->next();
  const shadow::FootprintDetail::Limits limits =
      s.detail->next(shadow::productFootprintPx(bundle_.view, s.spheres[pose.product], pose));
  d.passes = std::min(d.passes, limits.passes);
  d.shadowMapSize = std::min(d.shadowMapSize, limits.shadowMapSize);
  other += watch.lapNs();
  r.liveLighting = environmentLights(start);
  const int64_t environmentNs = watch.lapNs();
  const envmap::LightSet* lights = nullptr;
  if (r.liveLighting) {
    // One pass per light: the controller's pass count is the light count, taken along the
    // Halton prefix (envmap/live_lights.h), its map size as for the captured sources.
    lights = &s.live->lights(std::max<size_t>(d.passes, 1));
    s.loop.compositor.setShadowMapSize(d.shadowMapSize);
    s.loop.step(pose, *lights, s.background, s.live->fineLights());
  } else {
    s.loop.step(pose, d, s.background);
  }
  other += watch.lapNs() - s.loop.frameNs;
  r.stages = s.loop.stages;
  r.stages[FrameStage::kCamera] = cameraNs;
  r.stages[FrameStage::kEnvironment] = environmentNs;
  // Whatever the camera shows in front of the empty room stays in front of the product and
  // its shadow. Over the bundle's own photograph (no camera frame yet) nothing can.
  if (options_.hideForeground && camera.haveFrame) {
    r.foregroundPixels = static_cast<uint32_t>(s.foreground.showInFront(s.loop.rgba, s.background));
  }
  r.stages[FrameStage::kForeground] = watch.lapNs();
  r.frame = s.loop.frameNumber;
  const uint32_t passes = s.loop.stats.passes;
  const uint64_t passPixels = s.loop.renderer.lastStats().passPixels;
  const shadow::CompositeStats& c = s.loop.stats;
  io_.time->charge(
      {r.frame,
       start,
       {passes, passPixels, s.loop.renderer.lastStats().shadowMapTexels, c.productVertices,
        c.shadedVertices, c.transferredVertices, s.loop.renderer.lastStats().shadowMapTriangles}});
  noteBudget(start, d.overBudget);

  r.warnings = warnings(start, camera, d.overBudget);
  const LedState led = showLed(start, r.warnings);
  const uint32_t fps = fpsTenths(start);
  if (options_.hud == HudMode::kOn || (options_.hud == HudMode::kService && s.serviceHud)) {
    HudInfo h;
    h.fpsTenths = fps;
    h.passes = passes;
    h.shadowMapSize = d.shadowMapSize;
    h.product = bundle_.products[pose.product].name;
    h.mode = std::string(s.attract ? "ATTRACT" : (s.quality ? "QUALITY" : "FAST")) +
             (r.liveLighting ? " LIVE" : "");
    h.warnings = r.warnings;
    other += watch.lapNs();
    drawHud(s.loop.rgba, bundle_.view.width, bundle_.view.height, h);
    if (lights != nullptr) {
      // Below the top band, at the right edge.
      if (!s.inset) s.inset = std::make_unique<EnvironmentInset>();
      const int size = static_cast<int>(s.inset->size());
      s.inset->draw(s.environmentMap, *lights, options_.liveLights.toWorld, s.loop.rgba,
                    bundle_.view.width, bundle_.view.height,
                    static_cast<int>(bundle_.view.width) - size - 4, 26);
    }
    r.stages[FrameStage::kHud] = watch.lapNs();
  }
  other += watch.lapNs();
  if (io_.display != nullptr &&
      !io_.display->show(s.loop.rgba.data(), bundle_.view.width, bundle_.view.height)) {
    r.quit = true;
  }
  r.stages[FrameStage::kDisplay] = watch.lapNs();

  // 8. Pacing: the measured time goes back to the controller; the frame period is kept.
  const int64_t end = io_.time->nowNanoseconds();
  s.controller->report(end - start, passes, passPixels);
  const int64_t period = s.quality ? options_.qualityFrameNs : options_.fastFrameNs;
  if (end < start + period) io_.time->sleepUntil(start + period);

  r.endNs = end;
  r.workNs = end - start;
  r.passes = passes;
  r.passesAsked = d.passes;
  r.shadowMapSize = d.shadowMapSize;
  r.passPixels = passPixels;
  r.pose = pose;
  r.attract = s.attract;
  r.quality = s.quality;
  r.cameraFrameNew = s.frameNew;
  r.backgroundSequence = camera.haveFrame ? s.backgroundSequence : 0;
  r.backgroundAgeNs = camera.ageNs;
  r.latencyNs = camera.haveFrame ? end - s.backgroundCaptureNs : -1;
  r.stale = camera.stale;
  r.led = led;
  r.stages[FrameStage::kOther] = other + watch.lapNs();
  return r;
}

const std::vector<uint8_t>& KioskLoop::shownFrame() const {
  return s_->loop.rgba;
}

void KioskLoop::productReplaced(uint32_t index) {
  s_->loop.productModelChanged(index);
  s_->spheres[index] = shadow::yawSphere(bundle_.products[index].mesh);
}

void KioskLoop::setFault(const std::string& key, const std::string& hudText) {
  if (hudText.empty()) {
    s_->faults.erase(key);
  } else {
    s_->faults[key] = hudText;
  }
}

}  // namespace penumbra::kiosk
