#include "kiosk/status.h"

#include <stdexcept>
#include <utility>

namespace penumbra::kiosk {

const char* ledStateName(LedState s) {
  switch (s) {
    case LedState::kReady:
      return "ready";
    case LedState::kDegraded:
      return "degraded";
    case LedState::kError:
      return "error";
  }
  return "unknown";
}

const char* logLevelName(LogLevel level) {
  switch (level) {
    case LogLevel::kInfo:
      return "info";
    case LogLevel::kWarning:
      return "warning";
    case LogLevel::kError:
      return "error";
  }
  return "unknown";
}

KioskLog::KioskLog(std::FILE* echo, Options options) : echo_(echo), options_(options) {
  if (options_.capacity == 0) throw std::invalid_argument("KioskLog: capacity must be >= 1");
  if (options_.repeatWindowNs < 0) {
    throw std::invalid_argument("KioskLog: repeatWindowNs must be >= 0");
  }
  ring_.resize(options_.capacity);
}

void KioskLog::keep(int64_t timeNs, LogLevel level, std::string text) {
  if (text.size() > kMaxLineBytes) {
    text.resize(kMaxLineBytes - 3);
    text += "...";
  }
  if (echo_ != nullptr) {
    const int64_t ms = timeNs / 1'000'000;
    std::fprintf(echo_, "[%lld.%03lld] %s: %s\n", static_cast<long long>(ms / 1000),
                 static_cast<long long>(ms % 1000), logLevelName(level), text.c_str());
    std::fflush(echo_);
  }
  LogLine& slot = ring_[(head_ + count_) % ring_.size()];
  if (count_ == ring_.size()) {
    head_ = (head_ + 1) % ring_.size();  // the slot held the oldest line
    ++dropped_;
  } else {
    ++count_;
  }
  slot.timeNs = timeNs;
  slot.level = level;
  slot.text = std::move(text);  // reuses the slot's buffer when it is large enough
  lastWrittenNs_ = timeNs;
}

void KioskLog::flushRepeats() {
  if (repeats_ == 0) return;
  keep(latest_.timeNs, latest_.level,
       "last message repeated " + std::to_string(repeats_) + (repeats_ == 1 ? " time" : " times") +
           " (latest: " + latest_.text + ")");
  repeats_ = 0;
}

void KioskLog::write(int64_t timeNs, LogLevel level, const std::string& text,
                     const std::string& repeatKey) {
  if (level < options_.minLevel) return;
  // A named key cannot equal a text: it is marked with a byte no log text holds.
  std::string key = repeatKey.empty() ? text : '\x01' + repeatKey;
  if (haveLast_ && level == lastLevel_ && key == lastKey_) {
    ++repeats_;
    latest_ = {timeNs, level, text};
    if (timeNs - lastWrittenNs_ >= options_.repeatWindowNs) flushRepeats();
    return;
  }
  flushRepeats();
  keep(timeNs, level, text);
  lastKey_ = std::move(key);
  lastLevel_ = level;
  haveLast_ = true;
}

std::vector<LogLine> KioskLog::lines() const {
  std::vector<LogLine> out;
  out.reserve(count_);
  for (size_t i = 0; i < count_; ++i) out.push_back(at(i));
  return out;
}

bool KioskLog::contains(const std::string& needle, int64_t untilNs) const {
  for (size_t i = 0; i < count_; ++i) {
    const LogLine& l = at(i);
    if (l.timeNs <= untilNs && l.text.find(needle) != std::string::npos) return true;
  }
  return false;
}

}  // namespace penumbra::kiosk
