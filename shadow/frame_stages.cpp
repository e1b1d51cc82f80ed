#include "shadow/frame_stages.h"

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <span>

namespace penumbra::shadow {

const char* frameStageName(FrameStage stage) {
  switch (stage) {
    case FrameStage::kCamera:
      return "camera";
    case FrameStage::kPlacement:
      return "placement";
    case FrameStage::kShading:
      return "product shading";
    case FrameStage::kTraversal:
      return "traversal";
    case FrameStage::kClusters:
      return "clusters";
    case FrameStage::kRoomTransfers:
      return "room transfers";
    case FrameStage::kProductTransfers:
      return "product transfers";
    case FrameStage::kFrameContent:
      return "frame content";
    case FrameStage::kPassList:
      return "pass list";
    case FrameStage::kRasterObjects:
      return "raster objects";
    case FrameStage::kRasterPasses:
      return "raster passes";
    case FrameStage::kRasterFinish:
      return "raster finish";
    case FrameStage::kObserve:
      return "observe";
    case FrameStage::kHud:
      return "HUD";
    case FrameStage::kDisplay:
      return "display";
    case FrameStage::kOther:
      return "other";
    case FrameStage::kSimulatorCamera:
      return "simulator camera";
    case FrameStage::kCount:
      break;
  }
  return "?";
}

int64_t FrameStages::boardNs() const {
  int64_t sum = 0;
  for (size_t i = 0; i < kFrameStageCount; ++i) {
    if (static_cast<FrameStage>(i) != FrameStage::kSimulatorCamera) sum += ns[i];
  }
  return sum;
}

namespace {

double meanMsOf(std::span<const int64_t> v) {
  if (v.empty()) return 0;
  // Exact integer sum first: the means of the stages then add up to the mean frame.
  return double(std::accumulate(v.begin(), v.end(), int64_t{0})) * 1e-6 / double(v.size());
}

// The nearest-rank percentile, in ms; 0 when empty.
double percentileMsOf(std::span<const int64_t> samples, double p) {
  std::vector<int64_t> v(samples.begin(), samples.end());
  if (v.empty()) return 0;
  const size_t rank = std::min(v.size() - 1, static_cast<size_t>(p / 100.0 * double(v.size())));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(rank), v.end());
  return double(v[rank]) * 1e-6;
}

}  // namespace

void FrameStageSamples::reserve(size_t frames) {
  // resize, not reserve: the zeros touch every page now.
  for (auto& v : ns_) v.resize(std::max(v.size(), frames));
  board_.resize(std::max(board_.size(), frames));
}

void FrameStageSamples::add(const FrameStages& stages) {
  if (count_ == board_.size()) {
    for (auto& v : ns_) v.push_back(0);
    board_.push_back(0);
  }
  for (size_t i = 0; i < kFrameStageCount; ++i) ns_[i][count_] = stages.ns[i];
  board_[count_] = stages.boardNs();
  ++count_;
}

double FrameStageSamples::meanMs(FrameStage stage) const {
  return meanMsOf(std::span(ns_[static_cast<size_t>(stage)]).first(count_));
}

double FrameStageSamples::percentileMs(FrameStage stage, double p) const {
  return percentileMsOf(std::span(ns_[static_cast<size_t>(stage)]).first(count_), p);
}

double FrameStageSamples::meanBoardMs() const {
  return meanMsOf(std::span(board_).first(count_));
}

double FrameStageSamples::boardPercentileMs(double p) const {
  return percentileMsOf(std::span(board_).first(count_), p);
}

std::string FrameStageSamples::table() const {
  std::string out;
  char line[160];
  std::snprintf(line, sizeof line, "%-18s %9s %9s %9s %7s\n", "stage", "mean ms", "median", "p99",
                "share");
  out += line;
  const double board = meanBoardMs();
  const auto row = [&](const char* name, double mean, double median, double p99, double share) {
    std::snprintf(line, sizeof line, "%-18s %9.3f %9.3f %9.3f %6.1f%%\n", name, mean, median, p99,
                  share);
    out += line;
  };
  for (size_t i = 0; i < kFrameStageCount; ++i) {
    const auto stage = static_cast<FrameStage>(i);
    if (stage == FrameStage::kSimulatorCamera) continue;
    const double mean = meanMs(stage);
    if (mean == 0) continue;
    row(frameStageName(stage), mean, percentileMs(stage, 50), percentileMs(stage, 99),
        board > 0 ? 100 * mean / board : 0);
  }
  row("board frame", board, boardPercentileMs(50), boardPercentileMs(99), 100);
  const double camera = meanMs(FrameStage::kSimulatorCamera);
  if (camera > 0) {
    row("simulator camera", camera, percentileMs(FrameStage::kSimulatorCamera, 50),
        percentileMs(FrameStage::kSimulatorCamera, 99), board > 0 ? 100 * camera / board : 0);
  }
  return out;
}

}  // namespace penumbra::shadow
