#include "kiosk/buttons.h"

#include <algorithm>
#include <stdexcept>

namespace penumbra::kiosk {
namespace {

constexpr std::array<const char*, kButtonCount> kNames = {
    "next", "previous", "left", "right", "forward", "back", "rotate", "quality"};

bool repeats(Button b) {
  return b == Button::kLeft || b == Button::kRight || b == Button::kForward || b == Button::kBack ||
         b == Button::kRotate;
}

}  // namespace

const char* buttonName(Button b) {
  const auto i = static_cast<size_t>(b);
  return i < kButtonCount ? kNames[i] : "unknown";
}

std::optional<Button> parseButton(std::string_view name) {
  for (size_t i = 0; i < kButtonCount; ++i) {
    if (name == kNames[i]) return static_cast<Button>(i);
  }
  return std::nullopt;
}

Debouncer::Debouncer(Options options) : options_(options) {
  if (options_.settleNs < 0 || options_.repeatDelayNs <= 0 || options_.repeatNs <= 0 ||
      options_.stuckNs <= options_.settleNs) {
    throw std::invalid_argument(
        "Debouncer: settle >= 0, repeat delay and period > 0, stuck time > settle time");
  }
}

void Debouncer::settle(Line& line, Button b, int64_t nowNs, std::vector<ButtonAction>& actions,
                       std::vector<StuckChange>& stuck) {
  // A raw level that has held for settleNs becomes the stable level, dated when it started
  // to hold (so the action time does not depend on how often the kiosk polls).
  if (line.raw != line.stable && nowNs - line.rawSinceNs >= options_.settleNs) {
    line.stable = line.raw;
    line.stableSinceNs = line.rawSinceNs + options_.settleNs;
    if (line.stable) {
      actions.push_back({b, line.stableSinceNs, false});
      line.nextRepeatNs = line.stableSinceNs + options_.repeatDelayNs;
    } else if (line.stuck) {
      line.stuck = false;
      stuck.push_back({b, false, line.stableSinceNs});
    }
  }
  if (!line.stable || line.stuck) return;
  const int64_t stuckAt = line.stableSinceNs + options_.stuckNs;
  if (repeats(b)) {
    while (line.nextRepeatNs <= nowNs && line.nextRepeatNs < stuckAt) {
      actions.push_back({b, line.nextRepeatNs, true});
      line.nextRepeatNs += options_.repeatNs;
    }
  }
  if (nowNs >= stuckAt) {
    line.stuck = true;
    stuck.push_back({b, true, stuckAt});
  }
}

void Debouncer::update(const std::vector<RawEdge>& edges, int64_t nowNs,
                       std::vector<ButtonAction>& actions, std::vector<StuckChange>& stuck) {
  for (const RawEdge& e : edges) {
    const auto i = static_cast<size_t>(e.button);
    if (i >= kButtonCount) continue;
    Line& line = lines_[i];
    // Settle what held before this edge, then take the edge.
    settle(line, e.button, e.timeNs, actions, stuck);
    if (e.pressed != line.raw) {
      line.raw = e.pressed;
      line.rawSinceNs = e.timeNs;
    }
  }
  for (size_t i = 0; i < kButtonCount; ++i) {
    settle(lines_[i], static_cast<Button>(i), nowNs, actions, stuck);
  }
  // Lines were settled one after another: put the actions back in time order (stable, so
  // equal times keep the fixed line order).
  std::stable_sort(
      actions.begin(), actions.end(),
      [](const ButtonAction& a, const ButtonAction& b) { return a.timeNs < b.timeNs; });
}

bool Debouncer::anyStuck() const {
  for (const Line& l : lines_) {
    if (l.stuck) return true;
  }
  return false;
}

}  // namespace penumbra::kiosk
