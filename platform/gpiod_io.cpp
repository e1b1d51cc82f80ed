#include "platform/gpiod_io.h"

#include <chrono>
#include <ctime>
#include <gpiod.hpp>
#include <system_error>

namespace penumbra::platform {

namespace {

gpiod::chip openChip(const std::string& path) {
  try {
    return gpiod::chip(path, gpiod::chip::OPEN_BY_PATH);
  } catch (const std::exception& e) {
    throw HardwareUnavailable("gpio: cannot open chip " + path + ": " + e.what());
  }
}

int64_t monotonicNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

}  // namespace

struct GpiodButtons::Impl {
  GpioConfig config;
  gpiod::chip chip;
  std::array<gpiod::line, kiosk::kButtonCount> lines;
  int64_t lastEdgeNs = INT64_MIN;
};

GpiodButtons::GpiodButtons(const GpioConfig& config) : impl_(std::make_unique<Impl>()) {
  impl_->config = config;
  impl_->chip = openChip(config.chip);
  for (size_t i = 0; i < kiosk::kButtonCount; ++i) {
    const uint32_t offset = config.lines[i];
    try {
      impl_->lines[i] = impl_->chip.get_line(offset);
      impl_->lines[i].request(
          {"penumbra-kiosk", gpiod::line_request::EVENT_BOTH_EDGES,
           gpiod::line_request::FLAG_ACTIVE_LOW | gpiod::line_request::FLAG_BIAS_PULL_UP});
    } catch (const std::exception& e) {
      throw HardwareUnavailable("gpio: " + config.chip + " line " + std::to_string(offset) + " (" +
                                kiosk::buttonName(static_cast<kiosk::Button>(i)) +
                                "): cannot request it: " + e.what());
    }
  }
}

GpiodButtons::~GpiodButtons() = default;

void GpiodButtons::poll(int64_t nowNs, std::vector<kiosk::RawEdge>& out) {
  // Kernel event timestamps are CLOCK_MONOTONIC (Linux ≥ 5.7); map them onto the kiosk
  // clock by their age, so the debouncer sees the real bounce intervals.
  const int64_t mono = monotonicNs();
  for (size_t i = 0; i < kiosk::kButtonCount; ++i) {
    gpiod::line& line = impl_->lines[i];
    while (line.event_wait(std::chrono::nanoseconds(0))) {
      const gpiod::line_event ev = line.event_read();
      const int64_t age = mono - static_cast<int64_t>(ev.timestamp.count());
      int64_t t = nowNs - (age > 0 ? age : 0);
      if (t < impl_->lastEdgeNs) t = impl_->lastEdgeNs;  // keep time order across lines
      impl_->lastEdgeNs = t;
      out.push_back(
          {static_cast<kiosk::Button>(i), ev.event_type == gpiod::line_event::RISING_EDGE, t});
    }
  }
}

std::string GpiodButtons::describe() const {
  return "libgpiod " + impl_->config.chip + " (" + impl_->chip.label() + "), " +
         std::to_string(kiosk::kButtonCount) + " lines, pull-up, active low";
}

struct GpiodLed::Impl {
  gpiod::chip chip;
  gpiod::line line;
  bool on = false;
};

GpiodLed::GpiodLed(const GpioConfig& config) : impl_(std::make_unique<Impl>()) {
  if (config.ledLine < 0) throw HardwareUnavailable("gpio: no LED line configured");
  impl_->chip = openChip(config.chip);
  try {
    impl_->line = impl_->chip.get_line(static_cast<unsigned int>(config.ledLine));
    impl_->line.request({"penumbra-kiosk", gpiod::line_request::DIRECTION_OUTPUT, 0}, 0);
  } catch (const std::exception& e) {
    throw HardwareUnavailable("gpio: " + config.chip + " LED line " +
                              std::to_string(config.ledLine) + ": cannot request it: " + e.what());
  }
}

GpiodLed::~GpiodLed() = default;

void GpiodLed::set(kiosk::LedState state) {
  bool on = state == kiosk::LedState::kReady;
  if (state == kiosk::LedState::kDegraded) on = (monotonicNs() / 250'000'000) % 2 == 0;
  if (on != impl_->on) {
    impl_->line.set_value(on ? 1 : 0);
    impl_->on = on;
  }
}

}  // namespace penumbra::platform
