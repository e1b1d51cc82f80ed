// Frame-time drift (issue 18 §4: "frame time without drift, hashes of a replayed window
// identical"), measured on the same frames. Comparing the first and last thousand frames of a
// soak says little: the schedule decides what those frames draw (which product, where, how
// many passes), and their medians differed by content, not by age (2026-11-26: 4.88 against
// 5.97 ms at 20 000 frames, 5.87 against 4.98 ms at 6000, same build). Matching frames of
// equal content late and early failed as well: after 100 000 frames no product stood where
// it had at the start. So the soak's first frames are run a second time, in a new SimRun, in
// the same process after the whole soak: the same frames (their digests must be identical), drawn
// by a process that has run for hours. What differs is the process's age — heap fragmentation, the
// allocator's arenas, caches, the machine's state — which is what drift means here; a kiosk state
// that grows with age shows in the soak's memory lines instead.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "firmware-sim/sim_run.h"

namespace penumbra::firmware_sim {

// The median over i of second[i] / first[i] (the mean of the two middle ratios for an even
// count): 1 without drift. Pairs with a non-positive first time are left out; 0 when none is
// left. Throws std::invalid_argument when the spans differ in length.
double pairedMedianRatio(std::span<const int64_t> first, std::span<const int64_t> second);

class FrameTimeDrift {
 public:
  // Records the first `frames` frames of a run: storage allocated and written now, so that
  // recording allocates nothing (the soak's flat-memory check runs beside it).
  explicit FrameTimeDrift(uint32_t frames);

  // Records frame `r` and the SHA-256 of what it showed (scene::sha256), while fewer than
  // `frames` are held.
  void add(const kiosk::FrameReport& r, const std::array<uint8_t, 32>& shownDigest);
  uint32_t recorded() const { return count_; }
  bool full() const { return count_ == boardNs_.size(); }

  struct Result {
    uint32_t firstFrame = 0, lastFrame = 0;        // compared, 1-based, inclusive
    double firstMedianMs = 0, replayMedianMs = 0;  // nearest rank (firmware_sim::percentile)
    double ratio = 0;                              // pairedMedianRatio(first run, replay)
  };
  // Runs `session` again in a new SimRun for the recorded frames and compares the board
  // times of frames from `compareFrom` (1-based) on, pair by pair. Throws std::runtime_error
  // naming the first frame whose replayed picture differs from the recorded one.
  Result replay(const Session& session, const SimOptions& options, uint32_t compareFrom) const;

 private:
  std::vector<int64_t> boardNs_;
  std::vector<std::array<uint8_t, 32>> digests_;
  uint32_t count_ = 0;
};

}  // namespace penumbra::firmware_sim
