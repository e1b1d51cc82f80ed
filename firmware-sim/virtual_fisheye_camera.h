// The simulated environment camera of live lighting (issue 16 item 1; Havran et al. 2005 §5.1):
// a fisheye HDR camera looking at the zenith, whose frames are an EXR sequence (float RGB
// radiance) played on the virtual clock. envmap/fisheye_resampler.h turns a frame into the
// hemisphere map the light sampler reads; envmap/probe_sequences.h makes such sequences from
// light probes. Frame k is captured at k × period and shows sequence frame k mod count, so a
// session replays the same frames at the same virtual times.
//
// EXR through OpenCV (Debian's reads EXR with the system OpenEXR; design §6), because this
// layer does not see lighting/exr_io.h; the same rules as that reader: negative values (DWAA/
// DWAB ringing) become 0 and are counted, NaN and infinities are refused.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/image.h"

namespace penumbra::firmware_sim {

struct ExrSequence {
  std::vector<core::ImageF> frames;
  std::vector<std::string> names;  // file of each frame
  size_t clampedNegative = 0;      // samples below 0 set to 0, over all frames
};

// The EXR frames of a folder (its *.exr files) or a glob, in name order. Throws FootageError
// (footage.h) naming the file: unreadable, not 1 or 3 channels, of another size than the first,
// holding NaN or infinity, or more than `maxBytes` of frames in all.
ExrSequence loadExrSequence(const std::filesystem::path& source, size_t maxBytes = size_t{1} << 30);

class VirtualFisheyeCamera {
 public:
  // The paper's camera grabbed at about 21 Hz (Havran 2005 §3.3).
  static constexpr int64_t kDefaultPeriodNs = 47'619'048;

  // Throws std::invalid_argument for no frames, frames of different sizes or a period ≤ 0.
  VirtualFisheyeCamera(std::vector<core::ImageF> frames, int64_t periodNs = kDefaultPeriodNs);

  // The number of the newest frame captured at or before `nowNs` (−1 before the first).
  int64_t frameNumberAt(int64_t nowNs) const;
  // Copies the newest frame into `out` and its number into `k` when it is newer than the last
  // one grabbed; false (and nothing copied) otherwise.
  bool grab(int64_t nowNs, core::ImageF& out, uint64_t& k);
  std::string describe() const;

 private:
  std::vector<core::ImageF> frames_;
  int64_t periodNs_;
  int64_t lastGrabbed_ = -1;
};

}  // namespace penumbra::firmware_sim
