// Where one kiosk frame's time goes (issue 13): every stage of the whole frame, in the
// order the kiosk runs them, in wall-clock nanoseconds, so that a breakdown adds up to the
// frame it describes. FrameLoop fills the pipeline's stages (placement to observe); the
// kiosk adds the camera, the HUD and the display, and "other" takes what lies between the
// laps (button handling, the controller, the log), so that the board's stages sum to its
// whole frame exactly. The simulator's own rendering of its virtual camera is a stage of its
// own, outside the board's frame.
//
// Measurement only: nothing the kiosk decides reads these (the controller is told the frame
// time through the Timebase), so the simulator's frames stay identical bytes.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace penumbra::shadow {

enum class FrameStage : uint8_t {
  kCamera,            // grab the newest camera frame, convert it to RGBA8
  kEnvironment,       // live lighting: the environment camera's map into lights (Havran 2005)
  kPlacement,         // the product moved to its pose (product_placement)
  kShading,           // its colours and source transfers, when it moved (product_shading)
  kTraversal,         // Gibson 2003 §6.1 shaft traversal
  kClusters,          // §8 source clusters
  kRoomTransfers,     // clusters' transfers and S at the receiver vertices (§7.1.1)
  kProductTransfers,  // the same at the product's own vertices (§7.2 self-shadowing)
  kFrameContent,      // background, product mesh and colours into the frame description
  kPassList,          // one pass per cluster (Fig. 2)
  kRasterObjects,     // renderer: setup, binning, product composite
  kRasterPasses,      // renderer: shadow maps, S, probes' masks
  kRasterFinish,      // renderer: subtracting the sums, RGBA output
  kObserve,           // occlusion feedback for the next frame (docs/fig3.md)
  kForeground,        // the kiosk's mask of real things in front (kiosk/foreground_mask.h)
  kHud,               // the HUD drawn over the frame
  kDisplay,           // the frame handed to the display
  kOther,             // the rest of the kiosk's step: buttons, controller, log
  kSimulatorCamera,   // firmware-sim only: rendering the virtual camera's frame (not the board)
  kCount
};

constexpr size_t kFrameStageCount = static_cast<size_t>(FrameStage::kCount);

// A short name for tables ("room transfers").
const char* frameStageName(FrameStage stage);
// Every stage but the simulator's camera is the board's.
constexpr bool onBoard(FrameStage stage) {
  return stage != FrameStage::kSimulatorCamera;
}

struct FrameStages {
  std::array<int64_t, kFrameStageCount> ns{};

  int64_t& operator[](FrameStage s) { return ns[static_cast<size_t>(s)]; }
  int64_t operator[](FrameStage s) const { return ns[static_cast<size_t>(s)]; }
  // The board's frame: the sum of its stages (onBoard).
  int64_t boardNs() const;
};

// Stage times over many frames. Means add up: the stages' means sum to the mean board frame
// exactly (up to rounding), which medians do not; the medians and 99th percentiles say how
// each stage varies. Samples are kept: reserve() before the first frame allocates and
// touches room for that many, so the timed loop neither allocates nor faults pages in (only
// reserved, their pages came in as frames were added: the 100,000-frame soak's VmRSS rose
// ~160 kB per 1000 frames).
class FrameStageSamples {
 public:
  void reserve(size_t frames);
  void add(const FrameStages& stages);
  size_t frames() const { return count_; }
  double meanMs(FrameStage stage) const;
  double percentileMs(FrameStage stage, double p) const;
  double meanBoardMs() const;
  double boardPercentileMs(double p) const;
  // A table, one line per stage that took any time: mean, median, p99 (ms) and its share of
  // the mean board frame; then the board total and, apart, the simulator's camera.
  std::string table() const;
  // One line per frame: `frame`, then every stage's ms in FrameStage's order (columns named
  // by frameStageName, spaces as '_'), then `board_frame`; for finding which frames make the
  // p99 and what they spent it on.
  std::string csv() const;

 private:
  std::vector<int64_t> boardFrames() const;  // each added frame's boardNs()

  std::array<std::vector<int64_t>, kFrameStageCount> ns_;
  size_t count_ = 0;  // samples added; the vectors may be longer (reserve())
};

}  // namespace penumbra::shadow
