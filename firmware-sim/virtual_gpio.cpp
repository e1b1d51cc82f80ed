#include "firmware-sim/virtual_gpio.h"

#include <algorithm>

namespace penumbra::firmware_sim {

VirtualGpio::VirtualGpio(const std::vector<ScriptedPress>& presses) : presses_(presses.size()) {
  for (const ScriptedPress& p : presses) {
    const int64_t bounceSpan = 2 * static_cast<int64_t>(p.bounces) * p.bounceNs;
    if (p.holdNs <= bounceSpan || p.bounceNs <= 0 || p.atNs < 0) {
      throw std::invalid_argument("VirtualGpio: a press's bounces must end before its release");
    }
    // Press: closed, then `bounces` × (open, closed) a bounce interval apart; release likewise
    // ending open.
    for (bool pressing : {true, false}) {
      int64_t t = pressing ? p.atNs : p.atNs + p.holdNs;
      edges_.push_back({p.button, pressing, t});
      for (uint32_t b = 0; b < p.bounces; ++b) {
        edges_.push_back({p.button, !pressing, t += p.bounceNs});
        edges_.push_back({p.button, pressing, t += p.bounceNs});
      }
    }
  }
  std::stable_sort(
      edges_.begin(), edges_.end(),
      [](const kiosk::RawEdge& a, const kiosk::RawEdge& b) { return a.timeNs < b.timeNs; });
}

void VirtualGpio::poll(int64_t nowNs, std::vector<kiosk::RawEdge>& out) {
  while (next_ < edges_.size() && edges_[next_].timeNs <= nowNs) out.push_back(edges_[next_++]);
}

std::string VirtualGpio::describe() const {
  return "simulated GPIO, 8 lines, " + std::to_string(presses_) + " scripted presses";
}

}  // namespace penumbra::firmware_sim
