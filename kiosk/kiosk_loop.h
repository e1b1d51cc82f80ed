// The kiosk (issue 6): one loop, the same on the board and in the simulator (design.md §1,
// "per frame"): read the buttons, grab the newest camera frame as the background, let the
// frame-rate controller (Gibson 2003 §8) pick the passes, compose and render the product in
// the room, draw the HUD, show the frame, report the measured time.
//
// State machine: a product carousel (next/previous), moving the product on the floor and
// turning it, a quality toggle (more passes at 15 fps vs more frames at 30 fps), an idle
// attract mode that walks the product around the room by itself until a button is pressed.
//
// Faults: camera gone (reopened every second), late / dropped / duplicated / wrong frames,
// no buttons, stuck buttons, frames over budget. None stops the kiosk. Whenever the screen
// shows a camera frame older than `staleAfterNs` (a frozen picture) or no camera frame at all
// (the bundle's photograph instead), the LED is not `ready`, the HUD says so and the log has
// said so — the kiosk never shows a frozen frame silently.
//
// Determinism: everything the loop decides comes from its inputs and the Timebase. With the
// simulator's virtual timebase and cost model a whole session replays to identical bytes.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/clock.h"
#include "envmap/live_lights.h"
#include "kiosk/buttons.h"
#include "kiosk/environment_camera.h"
#include "kiosk/environment_inset.h"
#include "kiosk/foreground_mask.h"
#include "kiosk/frame_source.h"
#include "kiosk/hud.h"
#include "kiosk/status.h"
#include "raster/renderer.h"
#include "shadow/footprint_detail.h"
#include "shadow/frame_compositor.h"
#include "shadow/frame_cost_model.h"
#include "shadow/frame_rate_controller.h"
#include "shadow/frame_stages.h"
#include "shadow/scene_bundle.h"

namespace penumbra::kiosk {

// The rendering work of one frame, for a timebase that models its cost (the simulator).
struct FrameWork {
  uint32_t frame = 0;
  int64_t startNs = 0;
  shadow::CostModel::Workload work;
};

// The kiosk's clock. On the board: the steady clock, and time passes by itself. In the
// simulator: a virtual clock that charge() advances by a cost model.
class Timebase : public core::Clock {
 public:
  // Waits until `ns` (frame pacing: the kiosk does not run faster than its target rate).
  virtual void sleepUntil(int64_t ns) = 0;
  // Called once the frame's rendering work is done.
  virtual void charge(const FrameWork& work) { (void)work; }
};

class SteadyTimebase final : public Timebase {
 public:
  int64_t nowNanoseconds() override { return clock_.nowNanoseconds(); }
  void sleepUntil(int64_t ns) override;

 private:
  core::SteadyClock clock_;
};

// Who sees the HUD (frame rate, passes, mode, warnings): `kOn` always (development, the
// simulator); `kOff` never; `kService` (what a showroom runs) only after a technician holds
// `next` and `previous` together for `serviceHoldNs` — the two presses cancel out in the
// carousel — and until the next such hold.
enum class HudMode : uint32_t { kOff, kService, kOn };

struct KioskOptions {
  int64_t fastFrameNs = 33'333'333;     // fast mode: 30 fps (issue 6 target)
  int64_t qualityFrameNs = 66'666'667;  // quality mode: 15 fps, more passes
  int64_t fixedCostNs = 0;              // the controller's F̂ (underestimate, see its .h)
  // The bundle's settings (shadow/render_settings.h) lower maxPasses further and set the
  // shadow maps: their size, then its half and its quarter when the frame rate needs.
  uint32_t minPasses = 4, maxPasses = 64, initialPasses = 8;
  // Per frame, the product's footprint on screen caps the controller's passes and map size
  // (shadow/footprint_detail.h; fullDetailPx 0 turns it off).
  shadow::FootprintDetailOptions footprintDetail;
  int64_t attractAfterNs = 20'000'000'000;         // idle time before attract mode
  uint32_t attractMilliDegreesPerSecond = 12'000;  // how fast attract mode walks
  float moveStepMetres = 0.1f;
  float rotateStepDegrees = 15.0f;
  float floorMarginMetres = 0.6f;      // keep the product this far from the walls
  int64_t staleAfterNs = 100'000'000;  // camera frame older than this: say so
  int64_t reopenEveryNs = 1'000'000'000;
  HudMode hud = HudMode::kOn;
  int64_t serviceHoldNs = 3'000'000'000;
  FrameOrientation cameraOrientation;  // the camera mounting: toRgba mirrors every frame
  Debouncer::Options debounce;
  // Real things in front (issue 15 item 5): where the camera frame differs from the empty
  // room, its pixels are shown over the product and its shadow (kiosk/foreground_mask.h).
  bool hideForeground = true;
  ForegroundOptions foreground;
  // Live lighting (issue 16; Peripherals::environment): how the environment camera's maps
  // become lights — the Halton samples per map, the most lights (one shadow pass each; the
  // controller's pass count picks how many of them a frame uses), the camera's orientation
  // in the room and its radiance scale (envmap/live_lights.h).
  envmap::LiveLightsOptions liveLights;
  // No new environment frame for this long: said on the HUD and in the log, the lights of
  // the last frame kept.
  int64_t environmentStaleAfterNs = 500'000'000;
};

struct Peripherals {
  FrameSource* camera = nullptr;    // null: no camera — the bundle's photograph, said so
  ButtonSource* buttons = nullptr;  // null: no buttons — attract mode only, said so
  StatusLed* led = nullptr;         // required
  Display* display = nullptr;       // null: frames are only kept (simulator, tests)
  Timebase* time = nullptr;         // required
  KioskLog* log = nullptr;          // required
  // Live lighting: the environment camera whose frames light the product and cast its
  // shadows (KioskOptions::liveLights). Null: the captured sources of the bundle (Gibson
  // 2003). Until its first good frame, the captured sources too, said so.
  EnvironmentCamera* environment = nullptr;
};

// What happened in one frame (the simulator's summary, the tests' assertions).
struct FrameReport {
  uint32_t frame = 0;
  int64_t startNs = 0, endNs = 0;  // work start, frame shown
  int64_t workNs = 0;              // reported to the controller
  uint32_t passes = 0, passesAsked = 0, shadowMapSize = 0;
  uint32_t foregroundPixels = 0;  // of the product or its shadow, shown from the camera instead
  uint64_t passPixels = 0;
  shadow::ProductPose pose;
  bool attract = false, quality = false;
  bool cameraFrameNew = false;      // this frame's background is a new camera frame
  uint64_t backgroundSequence = 0;  // camera sequence shown (0: the bundle photograph)
  int64_t backgroundAgeNs = -1;     // now − capture of the shown frame; -1: no camera frame
  int64_t latencyNs = -1;           // capture → shown; -1 when no camera frame is shown
  bool stale = false;               // old or no camera frame on screen
  bool liveLighting = false;        // lit by the environment camera's lights this frame
  LedState led = LedState::kError;
  std::vector<std::string> warnings;  // as on the HUD
  bool quit = false;                  // the display asked to stop
  // Wall time of each stage of this step on the steady clock (shadow/frame_stages.h); they
  // sum to the step's wall time. Measurement only, never an input of the loop.
  shadow::FrameStages stages;
};

class KioskLoop {
 public:
  // `bundle` must outlive the loop. Throws std::invalid_argument when a required peripheral
  // is missing or the bundle has no usable product (validateProducts).
  KioskLoop(const shadow::SceneBundle& bundle, const KioskOptions& options, const Peripherals& io,
            const raster::RenderOptions& render);
  ~KioskLoop();
  KioskLoop(const KioskLoop&) = delete;
  KioskLoop& operator=(const KioskLoop&) = delete;

  // Runs one frame and shows it.
  FrameReport step();

  // The frame last shown (RGBA8, HUD included when enabled).
  const std::vector<uint8_t>& shownFrame() const;
  uint32_t width() const { return bundle_.view.width; }
  uint32_t height() const { return bundle_.view.height; }
  const std::vector<uint32_t>& carousel() const { return carousel_; }

  // The bundle's owner replaced product `index`'s model between two frames (a product file,
  // kiosk/product_files.h): the next frame places and shades it afresh.
  void productReplaced(uint32_t index);
  // A fault found outside the loop (a refused product file), keyed by what it concerns: on
  // the HUD and the LED degraded from the next frame until set again with an empty text.
  // Whoever found it has logged it.
  void setFault(const std::string& key, const std::string& hudText);

 private:
  struct State;
  void handleButtons(int64_t now);
  void serviceHold(int64_t now);
  void apply(const ButtonAction& a);
  void handleCamera(int64_t now);
  void rebuildController();
  shadow::ProductPose attractPose(int64_t now) const;
  // The stages of step(), in order.
  struct CameraStatus {
    bool haveFrame = false;  // a camera frame has ever arrived
    int64_t ageNs = -1;      // of the background, -1 without one
    bool stale = true;       // no new frame within options_.staleAfterNs
  };
  shadow::ProductPose inputAndPose(int64_t now);
  CameraStatus cameraBackground(int64_t now);
  // Live lighting: a new environment frame becomes the lights. True when this frame is lit
  // by them (a good environment frame has arrived).
  bool environmentLights(int64_t now);
  void noteBudget(int64_t now, bool overBudget);
  std::vector<std::string> warnings(int64_t now, const CameraStatus& camera, bool overBudget) const;
  LedState showLed(int64_t now, const std::vector<std::string>& warnings);
  uint32_t fpsTenths(int64_t now);
  void info(int64_t now, const std::string& text);
  void warn(int64_t now, const std::string& text);

  const shadow::SceneBundle& bundle_;
  KioskOptions options_;
  Peripherals io_;
  std::unique_ptr<State> s_;
  std::vector<uint32_t> carousel_;
};

// The products of `bundle` the kiosk can show: non-empty meshes and proxies, indices in
// range, finite positions, a proxy of at most 5,000 triangles and a fine proxy (when there
// is one) of at most 10,000. Each refused product is named in `why` (one line each).
std::vector<uint32_t> validateProducts(const shadow::SceneBundle& bundle,
                                       std::vector<std::string>& why);

}  // namespace penumbra::kiosk
