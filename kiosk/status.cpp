#include "kiosk/status.h"

#include <cstdio>
#include <stdexcept>

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
  // Every string the log keeps holds kMaxLineBytes from the start and lines are copied into
  // them, so writing allocates nothing after construction: a moved-in line would bring its
  // own buffer and free the slot's, and the heap grew line by line until the ring had filled
  // once (weeks at a quiet kiosk's rate). The repeat count's line is built in repeatLine_.
  ring_.resize(options_.capacity);
  for (LogLine& slot : ring_) slot.text.reserve(kMaxLineBytes);
  lastKey_.reserve(kMaxLineBytes);
  latest_.text.reserve(kMaxLineBytes);
  repeatLine_.reserve(kMaxLineBytes + 64);
}

// `s` cut to at most kMaxLineBytes bytes, marked "..." where it was cut, into `out`.
void KioskLog::assignCut(std::string& out, std::string_view s) {
  if (s.size() <= kMaxLineBytes) {
    out.assign(s);
  } else {
    out.assign(s.substr(0, kMaxLineBytes - 3));
    out.append("...");
  }
}

void KioskLog::keep(int64_t timeNs, LogLevel level, std::string_view text) {
  LogLine& slot = ring_[(head_ + count_) % ring_.size()];
  if (count_ == ring_.size()) {
    head_ = (head_ + 1) % ring_.size();  // the slot held the oldest line
    ++dropped_;
  } else {
    ++count_;
  }
  slot.timeNs = timeNs;
  slot.level = level;
  assignCut(slot.text, text);
  if (echo_ != nullptr) {
    const int64_t ms = timeNs / 1'000'000;
    std::fprintf(echo_, "[%lld.%03lld] %s: %s\n", static_cast<long long>(ms / 1000),
                 static_cast<long long>(ms % 1000), logLevelName(level), slot.text.c_str());
    std::fflush(echo_);
  }
  lastWrittenNs_ = timeNs;
}

void KioskLog::flushRepeats() {
  if (repeats_ == 0) return;
  char count[64];
  std::snprintf(count, sizeof count, "last message repeated %llu %s (latest: ",
                static_cast<unsigned long long>(repeats_), repeats_ == 1 ? "time" : "times");
  repeatLine_.assign(count).append(latest_.text).append(")");
  keep(latest_.timeNs, latest_.level, repeatLine_);
  repeats_ = 0;
}

void KioskLog::write(int64_t timeNs, LogLevel level, std::string_view text,
                     std::string_view repeatKey) {
  if (level < options_.minLevel) return;
  // The key is the text or, marked so that it cannot equal a text, the writer's key; both
  // compared as kept (cut at kMaxLineBytes).
  const bool named = !repeatKey.empty();
  const std::string_view key = (named ? repeatKey : text).substr(0, kMaxLineBytes);
  if (haveLast_ && level == lastLevel_ && named == lastKeyNamed_ && key == lastKey_) {
    ++repeats_;
    latest_.timeNs = timeNs;
    latest_.level = level;
    assignCut(latest_.text, text);
    if (timeNs - lastWrittenNs_ >= options_.repeatWindowNs) flushRepeats();
    return;
  }
  flushRepeats();
  keep(timeNs, level, text);
  lastKey_.assign(key);
  lastKeyNamed_ = named;
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
