#include "kiosk/status.h"

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

void KioskLog::write(int64_t timeNs, LogLevel level, const std::string& text) {
  lines_.push_back({timeNs, level, text});
  if (echo_ != nullptr) {
    static constexpr const char* kLevel[] = {"info", "warning", "error"};
    const int64_t ms = timeNs / 1'000'000;
    std::fprintf(echo_, "[%lld.%03lld] %s: %s\n", static_cast<long long>(ms / 1000),
                 static_cast<long long>(ms % 1000), kLevel[static_cast<int>(level)], text.c_str());
    std::fflush(echo_);
  }
}

bool KioskLog::contains(const std::string& needle, int64_t untilNs) const {
  for (const LogLine& l : lines_) {
    if (l.timeNs <= untilNs && l.text.find(needle) != std::string::npos) return true;
  }
  return false;
}

}  // namespace penumbra::kiosk
