#include "firmware-sim/soak.h"

#include <gtest/gtest.h>

#include <array>
#include <filesystem>

#include "firmware-sim/virtual_gpio.h"
#include "shadow/frame_cost_model.h"

namespace penumbra::firmware_sim {
namespace {

const std::filesystem::path kSoak = std::filesystem::path(PENUMBRA_DATA_DIR) / "sessions/soak.json";

TEST(Soak, ScheduleIsDeterministicAndCoversEveryKindOfEvent) {
  const Session base = loadSession(kSoak);
  const Session a = soakSession(base, 100'000), b = soakSession(base, 100'000);
  ASSERT_EQ(a.frames, 100'000u);
  ASSERT_EQ(a.presses.size(), b.presses.size());
  for (size_t i = 0; i < a.presses.size(); ++i) {
    ASSERT_EQ(a.presses[i].atNs, b.presses[i].atNs);
    ASSERT_EQ(a.presses[i].button, b.presses[i].button);
  }
  ASSERT_EQ(a.camera.faults.size(), b.camera.faults.size());
  ASSERT_EQ(a.loadSteps.size(), b.loadSteps.size());
  ASSERT_EQ(a.overruns.size(), b.overruns.size());

  // 100 000 frames at 30 fps ≈ 55 min: the documented densities.
  EXPECT_GT(a.presses.size(), 600u);
  EXPECT_GT(a.camera.faults.size(), 60u);
  EXPECT_GT(a.loadSteps.size(), 100u);
  EXPECT_GT(a.overruns.size(), 100u);
  std::array<int, kiosk::kButtonCount> buttons{};
  for (const ScriptedPress& p : a.presses) ++buttons[static_cast<size_t>(p.button)];
  for (int count : buttons) EXPECT_GT(count, 0);
  std::array<int, 6> kinds{};
  for (const CameraFault& f : a.camera.faults) ++kinds[static_cast<size_t>(f.kind)];
  for (int count : kinds) EXPECT_GT(count, 0);
  uint32_t heaviest = 0;
  for (const auto& s : a.loadSteps) heaviest = std::max(heaviest, s.permille);
  EXPECT_GE(heaviest, 20'000u) << "no heavy overload in the soak";

  // What the simulator needs of a schedule: presses that end before they bounce out, load
  // steps in strictly increasing time.
  EXPECT_NO_THROW(VirtualGpio{a.presses});
  EXPECT_NO_THROW(shadow::CostModel(a.cost, a.loadSteps));
  // A shorter soak is a prefix of a longer one (a window replays from the same schedule).
  const Session shortSoak = soakSession(base, 3'000);
  ASSERT_LE(shortSoak.presses.size(), a.presses.size());
  for (size_t i = 0; i < shortSoak.presses.size(); ++i) {
    EXPECT_EQ(shortSoak.presses[i].atNs, a.presses[i].atNs);
  }
}

}  // namespace
}  // namespace penumbra::firmware_sim
