// What a simulated session did, summed over its frames (penumbra-sim's report, the soak):
// camera-to-screen latency and camera outages, kept apart (issue 18). A frame whose picture
// the kiosk itself calls stale (frozen, lost, or older than stale_after_ms) after a camera
// frame had been shown belongs to an outage: its age is how long the camera has been gone,
// not how long a frame took to reach the screen, so it is counted in the outages and left
// out of the latency percentiles (a 2 s disconnect used to read as a p99 latency of
// 1996 ms). Frames before the first camera frame are neither.
#pragma once

#include <cstdint>
#include <vector>

#include "kiosk/kiosk_loop.h"

namespace penumbra::firmware_sim {

// Nearest rank: the smallest value with at least pct % of the samples at or below it; -1 for
// no samples.
int64_t percentile(std::vector<int64_t> values, int pct);

class SessionStats {
 public:
  // Reserves room for `frames` frames up front, so that adding them allocates nothing (the
  // soak's flat memory).
  explicit SessionStats(uint32_t frames);
  void add(const kiosk::FrameReport& r);
  // Closes an outage still open at the last frame (it lasts until that frame's end).
  void finish();

  // Latency of the frames showing a live camera frame.
  const std::vector<int64_t>& liveLatencyNs() const { return latency_; }
  uint32_t outages() const { return outages_; }
  int64_t outageTotalNs() const { return outageTotalNs_; }
  int64_t longestOutageNs() const { return longestOutageNs_; }

 private:
  void closeOutage(int64_t endNs);
  std::vector<int64_t> latency_;
  bool inOutage_ = false;
  int64_t outageStartNs_ = 0, lastEndNs_ = 0, outageTotalNs_ = 0, longestOutageNs_ = 0;
  uint32_t outages_ = 0;
};

}  // namespace penumbra::firmware_sim
