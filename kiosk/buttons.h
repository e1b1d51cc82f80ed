// The kiosk's buttons (design.md §2): raw edges from a ButtonSource (libgpiod, or the
// simulated GPIO timeline of firmware-sim/), cleaned by a software Debouncer (libgpiod 1.6
// has no debounce, design.md §6) into presses, with a stuck-button guard.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::kiosk {

// One line per function. Four move buttons or a joystick's four switches map to
// left/right/forward/back.
enum class Button : uint32_t {
  kNext,      // carousel: next product
  kPrevious,  // carousel: previous product
  kLeft,      // move on the floor (-x)
  kRight,     // +x
  kForward,   // -z (away from the camera's side of the room... see kiosk_loop.cpp)
  kBack,      // +z
  kRotate,    // turn the product by the rotate step
  kQuality,   // toggle: more passes (quality) vs more frames per second
};
inline constexpr size_t kButtonCount = 8;

const char* buttonName(Button b);  // "next", "previous", "left", ...
std::optional<Button> parseButton(std::string_view name);

// A change of a line's level; `pressed` after the change. Times on the kiosk clock.
struct RawEdge {
  Button button;
  bool pressed;
  int64_t timeNs;
};

class ButtonSource {
 public:
  virtual ~ButtonSource() = default;
  // Appends the edges that happened up to `nowNs`, in time order. Never blocks.
  virtual void poll(int64_t nowNs, std::vector<RawEdge>& out) = 0;
  virtual std::string describe() const = 0;
};

// What the kiosk acts on.
struct ButtonAction {
  Button button;
  int64_t timeNs;
  bool repeat;  // an auto-repeat of a held move/rotate button
};

// Software debounce: a level counts once it has been stable for `settleNs` (a mechanical
// switch bounces for 1-10 ms). A held move or rotate button repeats every `repeatNs`
// after `repeatDelayNs`. A button held longer than `stuckNs` is declared stuck: it stops
// acting (no endless repeat) until it is seen released.
class Debouncer {
 public:
  struct Options {
    int64_t settleNs = 20'000'000;
    int64_t repeatDelayNs = 400'000'000;
    int64_t repeatNs = 150'000'000;
    int64_t stuckNs = 5'000'000'000;
  };
  struct StuckChange {
    Button button;
    bool stuck;  // true: became stuck; false: released after being stuck
    int64_t timeNs;
  };

  explicit Debouncer(Options options);

  // Feeds raw edges (time order), then emits the actions and stuck changes up to `nowNs`.
  void update(const std::vector<RawEdge>& edges, int64_t nowNs, std::vector<ButtonAction>& actions,
              std::vector<StuckChange>& stuck);

  bool anyStuck() const;
  // The debounced level of a line, and since when it has held it.
  bool isDown(Button b) const { return lines_[static_cast<size_t>(b)].stable; }
  int64_t downSinceNs(Button b) const { return lines_[static_cast<size_t>(b)].stableSinceNs; }
  bool isStuck(Button b) const { return lines_[static_cast<size_t>(b)].stuck; }

 private:
  struct Line {
    bool raw = false;        // last raw level
    int64_t rawSinceNs = 0;  // time of the last raw edge
    bool stable = false;     // debounced level
    int64_t stableSinceNs = 0;
    int64_t nextRepeatNs = 0;
    bool stuck = false;
  };
  void settle(Line& line, Button b, int64_t nowNs, std::vector<ButtonAction>& actions,
              std::vector<StuckChange>& stuck);

  Options options_;
  std::array<Line, kButtonCount> lines_{};
};

}  // namespace penumbra::kiosk
