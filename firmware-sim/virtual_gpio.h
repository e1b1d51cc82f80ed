// The simulated twin of the kiosk's GPIO buttons (issue 6 §5): a scripted timeline of
// presses on the virtual clock, with contact bounce and stuck buttons, delivered as the raw
// edges libgpiod would report (EVENT_BOTH_EDGES) — the kiosk's software debounce does the rest.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "kiosk/buttons.h"

namespace penumbra::firmware_sim {

struct ScriptedPress {
  int64_t atNs = 0;
  kiosk::Button button = kiosk::Button::kNext;
  int64_t holdNs = 80'000'000;   // a long hold is a stuck button
  uint32_t bounces = 0;          // extra open/close pairs at press and at release
  int64_t bounceNs = 1'000'000;  // between bounce edges
};

// "No GPIO chip" on the board and in the simulator alike.
class GpioUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class VirtualGpio final : public kiosk::ButtonSource {
 public:
  // Throws std::invalid_argument if a press's bounces run past its own hold time.
  explicit VirtualGpio(const std::vector<ScriptedPress>& presses);
  void poll(int64_t nowNs, std::vector<kiosk::RawEdge>& out) override;
  std::string describe() const override;
  const std::vector<kiosk::RawEdge>& timeline() const { return edges_; }

 private:
  std::vector<kiosk::RawEdge> edges_;  // time order
  size_t next_ = 0;
  size_t presses_ = 0;
};

}  // namespace penumbra::firmware_sim
