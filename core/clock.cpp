#include "core/clock.h"

#include <chrono>
#include <limits>
#include <stdexcept>
#include <string>

namespace penumbra::core {
namespace {

// Stateless: one instance serves every default Stopwatch.
SteadyClock& steadyClock() {
  static SteadyClock clock;
  return clock;
}

}  // namespace

Stopwatch::Stopwatch() : Stopwatch(steadyClock()) {}

int64_t Stopwatch::lapNs() {
  const int64_t now = clock_.nowNanoseconds();
  const int64_t elapsed = now - lastNs_;
  lastNs_ = now;
  return elapsed;
}

double Stopwatch::lap() {
  return static_cast<double>(lapNs()) / 1e6;
}

int64_t SteadyClock::nowNanoseconds() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

VirtualClock::VirtualClock(int64_t startNs) : nowNs_(startNs) {}

void VirtualClock::advance(int64_t ns) {
  if (ns < 0) {
    throw std::invalid_argument("VirtualClock::advance: ns must be >= 0 (got " +
                                std::to_string(ns) + "); a clock never runs backwards");
  }
  if (nowNs_ > std::numeric_limits<int64_t>::max() - ns) {
    throw std::overflow_error("VirtualClock::advance: overflow");
  }
  nowNs_ += ns;
}

}  // namespace penumbra::core
