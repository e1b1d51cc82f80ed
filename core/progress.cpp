#include "core/progress.h"

#include <unistd.h>

#include <utility>

namespace penumbra::core {

bool stderrIsTerminal() {
  return isatty(STDERR_FILENO) == 1;
}

Progress::Progress(std::string label, bool terminal, std::FILE* out)
    : label_(std::move(label)), terminal_(terminal), out_(out) {}

namespace {

constexpr int kBarWidth = 24;

std::string bar(int filled) {
  std::string text(size_t(filled), '#');
  text.append(size_t(kBarWidth - filled), '-');
  return text;
}

}  // namespace

void Progress::draw(const std::string& text) {
  if (terminal_) {
    // Padding clears the tail of a longer previous line.
    std::fprintf(out_, "\r%-60s", text.c_str());
    lineOpen_ = true;
  } else {
    std::fprintf(out_, "%s\n", text.c_str());
  }
  std::fflush(out_);
}

void Progress::stage(const std::string& name, int index, int count) {
  const int filled = count > 0 ? kBarWidth * index / count : 0;
  char counter[32];
  std::snprintf(counter, sizeof counter, "%2d/%d", index + 1, count);
  const std::string prefix = label_.empty() ? "" : label_ + " ";
  draw(terminal_ ? prefix + "[" + bar(filled) + "] " + counter + " " + name
                 : prefix + counter + " " + name);
}

void Progress::fraction(uint64_t done, uint64_t total) {
  const int percent = total > 0 ? static_cast<int>(100 * done / total) : 100;
  // Off a terminal, a line per 10 %: enough to see a long run move, few enough for a log.
  const int step = terminal_ ? percent : percent / 10 * 10;
  if (step == lastPercent_) return;
  lastPercent_ = step;
  char text[96];
  if (terminal_) {
    std::snprintf(text, sizeof text, "%s [%s] %3d%%", label_.c_str(),
                  bar(kBarWidth * percent / 100).c_str(), percent);
  } else {
    std::snprintf(text, sizeof text, "%s %d%%", label_.c_str(), step);
  }
  draw(text);
  if (done >= total) finish();
}

void Progress::finish() {
  if (!lineOpen_) return;
  std::fprintf(out_, "\n");
  std::fflush(out_);
  lineOpen_ = false;
}

}  // namespace penumbra::core
