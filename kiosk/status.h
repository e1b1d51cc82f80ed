// The status LED and the screen behind small interfaces (design.md §2), and the kiosk's log.
// Real backends: libgpiod (LED line), SDL2 (screen); simulated ones record what they got.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace penumbra::kiosk {

// ready: camera frames flowing, buttons present, frame rate met. degraded: the kiosk runs
// but something is wrong and the screen may show an old camera frame (it says so). error:
// no usable scene — nothing sensible can be shown.
enum class LedState : uint8_t { kReady, kDegraded, kError };
const char* ledStateName(LedState s);

class StatusLed {
 public:
  virtual ~StatusLed() = default;
  virtual void set(LedState state) = 0;
};

class Display {
 public:
  virtual ~Display() = default;
  // Shows one RGBA8 frame (row 0 at the top). Returns false when the user asked to quit
  // (window closed); the kiosk then stops.
  virtual bool show(const uint8_t* rgba, uint32_t width, uint32_t height) = 0;
};

// A LED that only remembers (no LED wired, or the simulator).
class RecordingLed final : public StatusLed {
 public:
  void set(LedState state) override { state_ = state; }
  LedState state() const { return state_; }

 private:
  LedState state_ = LedState::kError;
};

enum class LogLevel : uint8_t { kInfo, kWarning, kError };

struct LogLine {
  int64_t timeNs;
  LogLevel level;
  std::string text;
};

// Kiosk log: timestamped on the kiosk clock (virtual in the simulator, so logs replay too).
// Keeps every line (tests read them) and optionally echoes to a stdio stream (journald
// takes the kiosk's stderr under systemd).
class KioskLog {
 public:
  explicit KioskLog(std::FILE* echo = nullptr) : echo_(echo) {}
  void write(int64_t timeNs, LogLevel level, const std::string& text);
  const std::vector<LogLine>& lines() const { return lines_; }
  // True when a line at or before `untilNs` contains `needle`.
  bool contains(const std::string& needle, int64_t untilNs = INT64_MAX) const;

 private:
  std::FILE* echo_;
  std::vector<LogLine> lines_;
};

}  // namespace penumbra::kiosk
