// A whole simulated kiosk session (issue 6 §5): the kiosk loop of platform/ with the
// simulated camera, GPIO and LED, on a virtual clock that the board's cost model advances
// (shadow::CostModel, plus scripted overruns). Every displayed frame is a pure function of
// the session file and the bundle: wall time never enters, so the per-frame hashes are the
// same for any thread count, SIMD target or machine (design.md §3).
#pragma once

#include <cstdio>
#include <memory>
#include <vector>

#include "firmware-sim/session.h"
#include "kiosk/bundle_guard.h"
#include "kiosk/kiosk_loop.h"

namespace penumbra::firmware_sim {

// The virtual clock with the board's cost model: charge() advances it by the modelled cost
// of the frame's work, sleepUntil() jumps to the deadline.
class SimTimebase final : public kiosk::Timebase {
 public:
  SimTimebase(shadow::CostModel model, std::vector<Overrun> overruns);
  int64_t nowNanoseconds() override { return clock_.nowNanoseconds(); }
  void sleepUntil(int64_t ns) override;
  void charge(const kiosk::FrameWork& work) override;

 private:
  core::VirtualClock clock_;
  shadow::CostModel model_;
  std::vector<Overrun> overruns_;
};

struct SimOptions {
  raster::RenderOptions render;
  std::FILE* logEcho = nullptr;  // echo the kiosk log (e.g. stderr)
};

// The best SIMD target of this CPU on one thread: the same frames as any other target (the
// bit-exact contract, checked by the invariance tests), the fastest a test of the kiosk's
// behaviour can run them without starting a thread. RenderOptions' default, the scalar
// target, spent 45 % of a fault session in its scalar mask kernel.
SimOptions bestTargetOneThread();

class SimRun {
 public:
  // Loads the bundle (with the session's start-up faults applied) and builds the loop.
  // Throws SessionError / kiosk::NoUsableBundle with the reason.
  SimRun(const Session& session, const SimOptions& options);
  ~SimRun();

  // Applies the product files due by now (hot-swaps), then runs one frame.
  kiosk::FrameReport step();
  const std::vector<uint8_t>& frame() const { return loop_->shownFrame(); }
  uint32_t width() const { return loop_->width(); }
  uint32_t height() const { return loop_->height(); }
  const kiosk::KioskLog& log() const { return log_; }
  kiosk::LedState led() const { return led_.state(); }
  const kiosk::GuardedBundle& bundle() const { return *bundle_; }
  const VirtualCamera* camera() const { return camera_.get(); }
  const kiosk::KioskLoop& loop() const { return *loop_; }

 private:
  kiosk::KioskLog log_;
  kiosk::RecordingLed led_;
  SimTimebase time_;
  std::unique_ptr<kiosk::GuardedBundle> bundle_;
  std::unique_ptr<VirtualCamera> camera_;
  std::unique_ptr<VirtualGpio> gpio_;
  std::unique_ptr<kiosk::EnvironmentCamera> environment_;  // session "environment"
  std::unique_ptr<kiosk::KioskLoop> loop_;
  std::vector<ScriptedProductFile> pendingProductFiles_;  // hot-swaps still to come
};

}  // namespace penumbra::firmware_sim
