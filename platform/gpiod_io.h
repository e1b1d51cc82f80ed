// The kiosk's buttons and status LED on libgpiod 1.6 (C++ bindings, design.md §6): one
// input line per button, requested for both edges with the internal pull-up and active-low
// (buttons switch to ground), read without blocking each frame; debouncing is the kiosk's
// (kiosk/buttons.h: libgpiod 1.6 has none). The LED is one output line.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "kiosk/buttons.h"
#include "kiosk/kiosk_config.h"
#include "kiosk/status.h"
#include "platform/hardware.h"

namespace penumbra::platform {

struct GpioConfig {
  std::string chip = "/dev/gpiochip0";
  // Line offsets in Button order; the defaults are docs/kiosk.md's wiring table.
  std::array<uint32_t, kiosk::kButtonCount> lines = kiosk::kDefaultButtonLines;
  int32_t ledLine = kiosk::kDefaultLedLine;  // -1: no LED
};

class GpiodButtons final : public kiosk::ButtonSource {
 public:
  // Throws HardwareUnavailable naming the chip (and the line) when the chip cannot be opened
  // or a line cannot be requested (missing, busy, no permission).
  explicit GpiodButtons(const GpioConfig& config);
  ~GpiodButtons() override;
  void poll(int64_t nowNs, std::vector<kiosk::RawEdge>& out) override;
  std::string describe() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// ready: on; degraded: blinking at 2 Hz (toggled by set(), from the kiosk clock); error: off.
class GpiodLed final : public kiosk::StatusLed {
 public:
  explicit GpiodLed(const GpioConfig& config);  // throws HardwareUnavailable
  ~GpiodLed() override;
  void set(kiosk::LedState state) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::platform
