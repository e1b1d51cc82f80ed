#include "firmware-sim/virtual_environment_camera.h"

#include <utility>

#include "firmware-sim/footage.h"

namespace penumbra::firmware_sim {
namespace {

envmap::FisheyeLens squareLens(const ExrSequence& sequence, const std::string& source) {
  if (sequence.frames.empty()) throw FootageError(source + ": no frames");
  const core::ImageF& f = sequence.frames[0];
  if (f.width != f.height) {
    throw FootageError(source + ": " + std::to_string(f.width) + "x" + std::to_string(f.height) +
                       " frames; the equidistant 180° fisheye fills a square image");
  }
  return envmap::FisheyeLens::equidistant180(f.width);
}

}  // namespace

VirtualEnvironmentCamera::VirtualEnvironmentCamera(ExrSequence&& sequence, std::string source,
                                                   int64_t periodNs, int64_t stopAtNs)
    : names_(std::move(sequence.names)),
      source_(std::move(source)),
      resampler_(squareLens(sequence, source_)),
      camera_(std::move(sequence.frames), periodNs),
      stopAtNs_(stopAtNs) {}

kiosk::GrabStatus VirtualEnvironmentCamera::grab(int64_t nowNs, envmap::HemisphereMap& map) {
  if (stopAtNs_ >= 0 && nowNs >= stopAtNs_) return kiosk::GrabStatus::kNoFrame;
  uint64_t k = 0;
  if (!camera_.grab(nowNs, image_, k)) return kiosk::GrabStatus::kNoFrame;
  resampler_.resample(image_, map, names_[k % names_.size()]);
  return kiosk::GrabStatus::kFrame;
}

std::string VirtualEnvironmentCamera::describe() const {
  return source_ + " (" + camera_.describe() + ")";
}

}  // namespace penumbra::firmware_sim
