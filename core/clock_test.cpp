#include "core/clock.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>

namespace penumbra::core {
namespace {

TEST(Clock, VirtualClockMovesOnlyWhenAdvanced) {
  VirtualClock c(5);
  EXPECT_EQ(c.nowNanoseconds(), 5);
  EXPECT_EQ(c.nowNanoseconds(), 5);
  c.advance(0);
  c.advance(1'000);
  EXPECT_EQ(c.nowNanoseconds(), 1'005);
  EXPECT_THROW(c.advance(-1), std::invalid_argument);
  EXPECT_EQ(c.nowNanoseconds(), 1'005);
}

TEST(Clock, SteadyClockNeverRunsBackwards) {
  SteadyClock c;
  int64_t prev = c.nowNanoseconds();
  for (int i = 0; i < 1000; ++i) {
    const int64_t now = c.nowNanoseconds();
    ASSERT_GE(now, prev);
    prev = now;
  }
}

TEST(Clock, StopwatchLapsAreMillisecondsSinceTheLastLap) {
  VirtualClock c(5'000);
  Stopwatch watch(c);
  c.advance(2'500'000);
  EXPECT_EQ(watch.lap(), 2.5);
  c.advance(1'000);
  EXPECT_EQ(watch.lap(), 0.001);
  EXPECT_EQ(watch.lap(), 0.0);
}

}  // namespace
}  // namespace penumbra::core
