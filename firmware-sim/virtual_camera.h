// The simulated twin of the kiosk camera (issue 6 §5): frames made from a still image (the
// bundle's photograph of the empty room) or from footage on the virtual clock, with scripted
// synthetic changes — exposure drift, a person walking through — and every camera fault the kiosk
// must survive: dropped, late and duplicated frames, frames of the wrong size or format, and the
// camera disappearing and coming back. Integers only: the same frames on every machine.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "kiosk/frame_source.h"

namespace penumbra::firmware_sim {

enum class CameraFaultKind { kDrop, kLate, kDuplicate, kWrongSize, kWrongFormat, kDisconnect };
const char* cameraFaultName(CameraFaultKind kind);

// Applies to camera frames [frame, frame + count) (frame k is captured at k × period).
struct CameraFault {
  CameraFaultKind kind;
  uint64_t frame = 0;
  uint64_t count = 1;
  int64_t delayNs = 0;  // kLate: extra delay before the frame reaches the kiosk
};

struct CameraScript {
  int64_t periodNs = 33'333'333;    // 30 fps sensor
  int64_t transportNs = 8'000'000;  // capture → in memory (readout + ISP + copy)
  // Exposure drift: gain 1 + amplitude·tri(k / period), a triangle wave in ‰.
  uint32_t driftPermille = 0;
  uint32_t driftPeriodFrames = 0;  // 0: no drift
  // A person (dark silhouette) walking from the left edge to the right one over camera
  // frames [personFrom, personTo); personTo == 0: nobody.
  uint64_t personFrom = 0, personTo = 0;
  uint32_t personWidth = 60, personHeight = 300;
  std::vector<CameraFault> faults;
};

class VirtualCamera final : public kiosk::FrameSource {
 public:
  // `still`: RGBA8 width × height, the scene the camera sees.
  VirtualCamera(std::vector<uint8_t> still, uint32_t width, uint32_t height, CameraScript script);
  // Footage (firmware-sim/footage.h): camera frame k films frames[k mod count], each RGBA8
  // width × height.
  VirtualCamera(std::vector<std::vector<uint8_t>> frames, uint32_t width, uint32_t height,
                CameraScript script);

  kiosk::GrabStatus grab(int64_t nowNs, kiosk::CameraFrame& out) override;
  bool reopen(int64_t nowNs) override;
  std::string describe() const override;

  // The image of camera frame k as the kiosk receives it (before any format fault): for
  // tests that compare what is shown with what was filmed.
  void render(uint64_t k, kiosk::CameraFrame& out) const;
  int64_t arrivalNs(uint64_t k) const;  // -1: dropped
  // Whether the walking person covers pixel (x, y) of camera frame k (the dark silhouette
  // render() draws there).
  bool personCovers(uint64_t k, uint32_t x, uint32_t y) const;
  // Wall time grab() spent rendering frames since the last call (the simulator's own work,
  // which a board's camera does in hardware: reported apart from the board's frame).
  int64_t takeRenderNs();

 private:
  // The person's body and head in camera frame k (empty boxes when nobody walks).
  struct PersonShape {
    int64_t px0 = 0, px1 = -1, bodyTop = 0, headTop = 0, bottom = 0, hx0 = 0, hx1 = -1;
    bool covers(int64_t x, int64_t y) const {
      return (x >= px0 && x <= px1 && y >= bodyTop && y < bottom) ||
             (x >= hx0 && x <= hx1 && y >= headTop && y < bodyTop - 4);
    }
  };
  PersonShape personShape(uint64_t k) const;
  bool faulted(CameraFaultKind kind, uint64_t k, const CameraFault** which = nullptr) const;
  void timedRender(uint64_t k, kiosk::CameraFrame& out);  // render(), timed into renderNs_
  bool disconnectedAt(int64_t nowNs) const;

  std::vector<std::vector<uint8_t>> frames_;
  uint32_t width_, height_;
  CameraScript script_;
  bool open_ = true;
  bool delivered_ = false;
  uint64_t lastDelivered_ = 0;  // frame index
  bool duplicatePending_ = false;
  int64_t renderNs_ = 0;
};

}  // namespace penumbra::firmware_sim
