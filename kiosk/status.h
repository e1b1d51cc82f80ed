// The status LED and the screen behind small interfaces (design.md §2), and the kiosk's log.
// Real backends: libgpiod (LED line), SDL2 (screen); simulated ones record what they got.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
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
const char* logLevelName(LogLevel level);

struct LogLine {
  int64_t timeNs;
  LogLevel level;
  std::string text;
};

// Kiosk log: timestamped on the kiosk clock (virtual in the simulator, so logs replay too),
// optionally echoed to a stdio stream (journald takes the kiosk's stderr under systemd).
// A kiosk runs for months, so the log's memory is fixed (issue 18):
//  - a ring of `capacity` lines: the oldest line goes when a new one comes (dropped() counts
//    them), and a line's text is cut at kMaxLineBytes;
//  - lines below `minLevel` are neither kept nor echoed;
//  - a line of the same level and the same repeat key as the one before is counted, not
//    kept. The key is the text itself, or what the writer names: a message that carries a
//    changing number every frame ("camera: frame 31 refused: ...", "... frame 32 ...") is
//    written with a fixed key, so it repeats even though its text differs. The count goes out as
//    one line "last message repeated N times (latest: ...)" when another line comes or
//    `repeatWindowNs` after the last line written, so a camera that sends a wrong frame every frame
//    costs one line per window, not per frame.
class KioskLog {
 public:
  static constexpr size_t kMaxLineBytes = 512;
  struct Options {
    size_t capacity = 1024;
    LogLevel minLevel = LogLevel::kInfo;
    int64_t repeatWindowNs = 10'000'000'000;  // 10 s
  };
  explicit KioskLog(std::FILE* echo = nullptr) : KioskLog(echo, Options{}) {}
  // Throws std::invalid_argument for a zero capacity or a negative window.
  KioskLog(std::FILE* echo, Options options);
  // Allocates nothing: lines are copied into strings reserved at construction.
  void write(int64_t timeNs, LogLevel level, std::string_view text,
             std::string_view repeatKey = {});
  // The kept lines, oldest first (at most `capacity`; a pending repeat count is not a line
  // until it is written out).
  std::vector<LogLine> lines() const;
  size_t size() const { return count_; }
  uint64_t dropped() const { return dropped_; }
  // True when a kept line at or before `untilNs` contains `needle`.
  bool contains(const std::string& needle, int64_t untilNs = INT64_MAX) const;

 private:
  static void assignCut(std::string& out, std::string_view s);
  void keep(int64_t timeNs, LogLevel level, std::string_view text);
  void flushRepeats();
  const LogLine& at(size_t i) const { return ring_[(head_ + i) % ring_.size()]; }

  std::FILE* echo_;
  Options options_;
  std::vector<LogLine> ring_;  // capacity slots, allocated once
  size_t head_ = 0, count_ = 0;
  uint64_t dropped_ = 0;
  // The run of repeats of the last kept line: its key, how many were counted, the
  // latest one, and when a line of the run was last written out.
  std::string lastKey_;
  bool lastKeyNamed_ = false;  // lastKey_ is a writer's key, not the text
  LogLevel lastLevel_ = LogLevel::kInfo;
  bool haveLast_ = false;
  std::string repeatLine_;  // "last message repeated N times (latest: ...)" is built here
  uint64_t repeats_ = 0;
  LogLine latest_{0, LogLevel::kInfo, {}};
  int64_t lastWrittenNs_ = 0;
};

}  // namespace penumbra::kiosk
