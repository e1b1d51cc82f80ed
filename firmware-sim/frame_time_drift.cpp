#include "firmware-sim/frame_time_drift.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "firmware-sim/session_stats.h"
#include "scene/sha256.h"

namespace penumbra::firmware_sim {
namespace {

double medianOf(std::vector<double> v) {
  if (v.empty()) return 0;
  const size_t n = v.size();
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n / 2), v.end());
  const double upper = v[n / 2];
  if (n % 2) return upper;
  return 0.5 *
         (*std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n / 2)) + upper);
}

double medianMs(std::span<const int64_t> ns) {
  return double(percentile(std::vector<int64_t>(ns.begin(), ns.end()), 50)) * 1e-6;
}

}  // namespace

double pairedMedianRatio(std::span<const int64_t> first, std::span<const int64_t> second) {
  if (first.size() != second.size()) {
    throw std::invalid_argument("pairedMedianRatio: " + std::to_string(first.size()) +
                                " first times against " + std::to_string(second.size()));
  }
  std::vector<double> ratios;
  ratios.reserve(first.size());
  for (size_t i = 0; i < first.size(); ++i)
    if (first[i] > 0) ratios.push_back(double(second[i]) / double(first[i]));
  return medianOf(std::move(ratios));
}

FrameTimeDrift::FrameTimeDrift(uint32_t frames) : boardNs_(frames, 0), digests_(frames) {}

void FrameTimeDrift::add(const kiosk::FrameReport& r, const std::array<uint8_t, 32>& shownDigest) {
  if (full()) return;
  boardNs_[count_] = r.stages.boardNs();
  digests_[count_] = shownDigest;
  ++count_;
}

FrameTimeDrift::Result FrameTimeDrift::replay(const Session& session, const SimOptions& options,
                                              uint32_t compareFrom) const {
  if (compareFrom < 1 || compareFrom > count_) {
    throw std::invalid_argument("FrameTimeDrift::replay: frame " + std::to_string(compareFrom) +
                                " is not among the " + std::to_string(count_) + " recorded");
  }
  SimRun run(session, options);
  std::vector<int64_t> replayNs(count_, 0);
  for (uint32_t f = 0; f < count_; ++f) {
    const kiosk::FrameReport r = run.step();
    replayNs[f] = r.stages.boardNs();
    if (scene::sha256(run.frame()) != digests_[f]) {
      throw std::runtime_error("soak replay: frame " + std::to_string(f + 1) +
                               " differs from the same frame of the first run");
    }
  }
  const std::span<const int64_t> first(boardNs_.data() + compareFrom - 1, count_ - compareFrom + 1);
  const std::span<const int64_t> again(replayNs.data() + compareFrom - 1, first.size());
  Result result;
  result.firstFrame = compareFrom;
  result.lastFrame = count_;
  result.firstMedianMs = medianMs(first);
  result.replayMedianMs = medianMs(again);
  result.ratio = pairedMedianRatio(first, again);
  return result;
}

}  // namespace penumbra::firmware_sim
