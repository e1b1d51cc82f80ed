// The simulated board's environment camera (issue 16 item 1): the virtual fisheye camera
// (virtual_fisheye_camera.h: an EXR sequence played on the virtual clock) behind the kiosk's
// EnvironmentCamera interface, each new frame resampled into the hemisphere map through the
// lens's fixed kernel (envmap/fisheye_resampler.h) — the work the board does per environment
// frame. The lens is the ideal equidistant 180° fisheye whose image circle fills the square
// frames (FisheyeLens::equidistant180), as envmap/probe_sequences.h's sequences are made.
// With OpenCV only (EXR reading, cv::fisheye).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "envmap/fisheye_resampler.h"
#include "firmware-sim/virtual_fisheye_camera.h"
#include "kiosk/environment_camera.h"

namespace penumbra::firmware_sim {

class VirtualEnvironmentCamera final : public kiosk::EnvironmentCamera {
 public:
  // `source` names the sequence in messages. Frames stop at `stopAtNs` (a camera that hangs;
  // < 0: never). Throws FootageError naming `source` for non-square frames.
  VirtualEnvironmentCamera(ExrSequence&& sequence, std::string source, int64_t periodNs,
                           int64_t stopAtNs = -1);

  kiosk::GrabStatus grab(int64_t nowNs, envmap::HemisphereMap& map) override;
  std::string describe() const override;

 private:
  std::vector<std::string> names_;
  std::string source_;
  envmap::FisheyeResampler resampler_;  // before camera_, which takes the frames
  VirtualFisheyeCamera camera_;
  int64_t stopAtNs_;
  core::ImageF image_;
};

}  // namespace penumbra::firmware_sim
