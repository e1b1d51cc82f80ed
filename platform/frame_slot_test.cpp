// The latest-frame mailbox with a real producer thread, as libcamera's completion thread
// drives it (also run under ThreadSanitizer: the tsan preset builds this test).
#include "platform/frame_slot.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <thread>

namespace penumbra::platform {
namespace {

using namespace std::chrono_literals;

// Every byte of frame k is k mod 251: a frame torn between two puts would mix values.
void fill(kiosk::CameraFrame& f, uint64_t k) {
  f.width = 64, f.height = 8, f.stride = 256, f.format = kiosk::PixelFormat::kXrgb8888;
  f.sequence = k;
  f.data.resize(256 * 8);
  std::fill(f.data.begin(), f.data.end(), static_cast<uint8_t>(k % 251));
}

TEST(FrameSlot, ProducerThreadHandsOverNewestFramesWhole) {
  constexpr uint64_t kFrames = 3000;
  FrameSlot slot;
  std::thread producer([&] {
    kiosk::CameraFrame f;
    for (uint64_t k = 1; k <= kFrames; ++k) {
      fill(f, k);
      ASSERT_TRUE(slot.put(f));
      if (k % 7 == 0) std::this_thread::yield();
    }
    slot.close();
  });
  kiosk::CameraFrame got;
  uint64_t last = 0, taken = 0;
  while (last < kFrames) {
    if (!slot.waitAndTake(got, 200ms)) {
      if (slot.closed() && !slot.take(got)) break;
      continue;
    }
    ++taken;
    ASSERT_GT(got.sequence, last) << "went back in time";
    last = got.sequence;
    const uint8_t v = static_cast<uint8_t>(got.sequence % 251);
    ASSERT_TRUE(std::all_of(got.data.begin(), got.data.end(), [&](uint8_t b) { return b == v; }))
        << "frame " << got.sequence << " torn";
  }
  producer.join();
  EXPECT_EQ(last, kFrames) << "the newest frame must reach the consumer";
  // Each frame was either taken or replaced before it could be: nothing lost silently.
  EXPECT_EQ(taken + slot.overwritten(), kFrames);
  EXPECT_FALSE(slot.take(got));
}

TEST(FrameSlot, KeepsOnlyTheNewestAndRecyclesBuffers) {
  FrameSlot slot;
  kiosk::CameraFrame a, b, out;
  fill(a, 1);
  fill(b, 2);
  ASSERT_TRUE(slot.put(a));
  EXPECT_TRUE(a.data.empty()) << "the producer gets the slot's (empty) buffer back";
  ASSERT_TRUE(slot.put(b));
  EXPECT_EQ(b.sequence, 1u) << "the frame it replaced comes back for reuse";
  EXPECT_EQ(slot.overwritten(), 1u);
  ASSERT_TRUE(slot.take(out));
  EXPECT_EQ(out.sequence, 2u);
  EXPECT_FALSE(slot.take(out));
}

TEST(FrameSlot, CloseWakesTheConsumerAndRefusesFrames) {
  FrameSlot slot;
  kiosk::CameraFrame f, out;
  std::thread closer([&] {
    std::this_thread::sleep_for(20ms);
    slot.close();
  });
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(slot.waitAndTake(out, 10s));
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 5s) << "close() did not wake the consumer";
  closer.join();
  fill(f, 5);
  EXPECT_FALSE(slot.put(f));
  EXPECT_EQ(f.sequence, 5u) << "a refused frame stays with the producer";
  slot.reopen();
  EXPECT_TRUE(slot.put(f));
  EXPECT_TRUE(slot.waitAndTake(out, 1s));
  EXPECT_EQ(out.sequence, 5u);
}

}  // namespace
}  // namespace penumbra::platform
