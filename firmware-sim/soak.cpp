#include "firmware-sim/soak.h"

#include <algorithm>

#include "core/random.h"

namespace penumbra::firmware_sim {
namespace {

constexpr uint64_t kSoakKey = 0x50a4'50a4'50a4'50a4ull;

// Draw `counter` of stream `stream`, in [0, n).
uint64_t draw(uint64_t stream, uint64_t counter, uint64_t n) {
  return core::splitmix64(core::splitmix64(kSoakKey ^ stream) + counter) % n;
}

}  // namespace

Session soakSession(Session base, uint32_t frames) {
  Session s = std::move(base);
  s.frames = frames;
  const int64_t frameNs = s.kiosk.fastFrameNs;
  const int64_t endNs = static_cast<int64_t>(frames) * frameNs;

  // A visitor: a press every 1.5-4.5 s; now and then a bouncing contact or a held button.
  s.presses.clear();
  int64_t t = 500 * kNsPerMs;
  for (uint64_t i = 0; t < endNs; ++i) {
    ScriptedPress p;
    p.atNs = t;
    p.button = static_cast<kiosk::Button>(draw(1, i, kiosk::kButtonCount));
    p.bounces = static_cast<uint32_t>(draw(2, i, 4));
    p.holdNs = (draw(3, i, 10) == 0 ? 1'500 : 80) * kNsPerMs;  // 1 in 10 held (moves repeat)
    s.presses.push_back(p);
    t += (1'500 + static_cast<int64_t>(draw(4, i, 3'000))) * kNsPerMs + p.holdNs;
  }

  // The camera: a fault every 20-40 s; one in six is a 1-3 s disconnect.
  s.camera.faults.clear();
  const uint64_t cameraFrames = static_cast<uint64_t>(endNs / s.camera.periodNs);
  uint64_t k = 60;
  for (uint64_t i = 0; k < cameraFrames; ++i) {
    CameraFault f;
    f.kind = static_cast<CameraFaultKind>(draw(5, i, 6));
    f.frame = k;
    f.count = 1 + draw(6, i, 4);
    if (f.kind == CameraFaultKind::kLate)
      f.delayNs = (50 + static_cast<int64_t>(draw(7, i, 200))) * kNsPerMs;
    if (f.kind == CameraFaultKind::kDisconnect) f.count = 30 + draw(8, i, 60);
    s.camera.faults.push_back(f);
    k += f.count + 600 + draw(9, i, 600);
  }

  // The board: the load steps every 20-40 s to 0.5×-4× or, one in eight, 20×-100× for a
  // few seconds; back to nominal in between.
  s.loadSteps.clear();
  t = 10'000 * kNsPerMs;
  for (uint64_t i = 0; t < endNs; ++i) {
    const bool heavy = draw(10, i, 8) == 0;
    const uint32_t permille = heavy ? static_cast<uint32_t>(20'000 + draw(11, i, 80'001))
                                    : static_cast<uint32_t>(500 + draw(11, i, 3'501));
    s.loadSteps.push_back({t, permille});
    const int64_t hold = (heavy ? 1'000 + static_cast<int64_t>(draw(12, i, 4'000))
                                : 5'000 + static_cast<int64_t>(draw(12, i, 15'000))) *
                         kNsPerMs;
    s.loadSteps.push_back({t + hold, 1000});
    t += hold + (10'000 + static_cast<int64_t>(draw(13, i, 20'000))) * kNsPerMs;
  }

  // Single-frame overruns of 20-120 ms every 10-30 s.
  s.overruns.clear();
  for (uint64_t i = 0, f = 200; f <= frames; ++i) {
    s.overruns.push_back(
        {static_cast<uint32_t>(f), (20 + static_cast<int64_t>(draw(14, i, 101))) * kNsPerMs});
    f += 300 + draw(15, i, 600);
  }
  return s;
}

}  // namespace penumbra::firmware_sim
