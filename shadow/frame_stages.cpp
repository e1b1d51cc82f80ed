#include "shadow/frame_stages.h"

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <numeric>
#include <span>

namespace penumbra::shadow {

namespace {

// In FrameStage's order, one per stage.
constexpr const char* kNames[] = {"camera",          "environment lights",
                                  "placement",       "product shading",
                                  "traversal",       "clusters",
                                  "room transfers",  "product transfers",
                                  "frame content",   "pass list",
                                  "raster objects",  "raster passes",
                                  "raster finish",   "observe",
                                  "foreground",      "HUD",
                                  "display",         "other",
                                  "simulator camera"};
static_assert(std::size(kNames) == kFrameStageCount);

}  // namespace

const char* frameStageName(FrameStage stage) {
  return stage < FrameStage::kCount ? kNames[static_cast<size_t>(stage)] : "?";
}

int64_t FrameStages::boardNs() const {
  int64_t sum = 0;
  for (size_t i = 0; i < kFrameStageCount; ++i) {
    if (onBoard(static_cast<FrameStage>(i))) sum += ns[i];
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
}

void FrameStageSamples::add(const FrameStages& stages) {
  for (size_t i = 0; i < kFrameStageCount; ++i) {
    if (count_ == ns_[i].size()) ns_[i].push_back(0);
    ns_[i][count_] = stages.ns[i];
  }
  ++count_;
}

std::vector<int64_t> FrameStageSamples::boardFrames() const {
  std::vector<int64_t> board(count_, 0);
  for (size_t i = 0; i < kFrameStageCount; ++i) {
    if (!onBoard(static_cast<FrameStage>(i))) continue;
    for (size_t f = 0; f < count_; ++f) board[f] += ns_[i][f];
  }
  return board;
}

double FrameStageSamples::meanMs(FrameStage stage) const {
  return meanMsOf(std::span(ns_[static_cast<size_t>(stage)]).first(count_));
}

double FrameStageSamples::percentileMs(FrameStage stage, double p) const {
  return percentileMsOf(std::span(ns_[static_cast<size_t>(stage)]).first(count_), p);
}

double FrameStageSamples::meanBoardMs() const {
  return meanMsOf(boardFrames());
}

double FrameStageSamples::boardPercentileMs(double p) const {
  return percentileMsOf(boardFrames(), p);
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
    if (!onBoard(stage)) continue;
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

std::string FrameStageSamples::csv() const {
  std::string out = "frame";
  for (size_t i = 0; i < kFrameStageCount; ++i) {
    std::string name = kNames[i];
    std::replace(name.begin(), name.end(), ' ', '_');
    out += ',' + name;
  }
  out += ",board_frame\n";
  const std::vector<int64_t> board = boardFrames();
  char cell[32];
  for (size_t f = 0; f < count_; ++f) {
    out += std::to_string(f + 1);
    for (size_t i = 0; i < kFrameStageCount; ++i) {
      std::snprintf(cell, sizeof cell, ",%.3f", double(ns_[i][f]) * 1e-6);
      out += cell;
    }
    std::snprintf(cell, sizeof cell, ",%.3f\n", double(board[f]) * 1e-6);
    out += cell;
  }
  return out;
}

}  // namespace penumbra::shadow
