#include "firmware-sim/session_stats.h"

#include <algorithm>

namespace penumbra::firmware_sim {

int64_t percentile(std::vector<int64_t> v, int pct) {
  if (v.empty()) return -1;
  std::sort(v.begin(), v.end());
  size_t rank = (v.size() * static_cast<size_t>(pct) + 99) / 100;
  if (rank == 0) rank = 1;
  return v[rank - 1];
}

SessionStats::SessionStats(uint32_t frames) {
  // Written once (resize), then emptied: reserve() alone leaves the pages untouched, and they
  // came in as frames were added, 8 bytes a frame, which the soak read as the kiosk's growth.
  latency_.resize(frames);
  latency_.clear();
}

void SessionStats::add(const kiosk::FrameReport& r) {
  const bool cameraShown = r.latencyNs >= 0;
  const bool out = cameraShown && r.stale;
  if (out && !inOutage_) {
    inOutage_ = true;
    outageStartNs_ = r.startNs;
    ++outages_;
  } else if (!out && inOutage_) {
    closeOutage(r.startNs);
  }
  if (cameraShown && !r.stale) latency_.push_back(r.latencyNs);
  lastEndNs_ = r.endNs;
}

void SessionStats::finish() {
  if (inOutage_) closeOutage(lastEndNs_);
}

void SessionStats::closeOutage(int64_t endNs) {
  inOutage_ = false;
  outageTotalNs_ += endNs - outageStartNs_;
  longestOutageNs_ = std::max(longestOutageNs_, endNs - outageStartNs_);
}

}  // namespace penumbra::firmware_sim
