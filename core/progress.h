// Progress of a long run, on stderr. On a terminal: one line redrawn in place
// ("[########----------------]  5/11 light probe", "reference [####....]  40%"). Anywhere else
// (a log file, CI, a pipe): plain lines, one per stage or per 10 %, because carriage returns
// turn a log into one line of thousands of redraws.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

namespace penumbra::core {

// Whether stderr is a terminal (isatty).
bool stderrIsTerminal();

class Progress {
 public:
  // Writes to `out`, redrawing in place when `terminal`.
  explicit Progress(std::string label, bool terminal = stderrIsTerminal(), std::FILE* out = stderr);

  // Stage `index` (0-based) of `count` starts.
  void stage(const std::string& name, int index, int count);
  // `done` of `total` items are finished; ends the line when done == total.
  void fraction(uint64_t done, uint64_t total);
  // The run finished: ends the redrawn line (a no-op when nothing was drawn or already ended).
  void finish();

 private:
  void draw(const std::string& text);

  std::string label_;
  bool terminal_;
  std::FILE* out_;
  int lastPercent_ = -1;
  bool lineOpen_ = false;
};

}  // namespace penumbra::core
