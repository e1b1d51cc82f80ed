#include "firmware-sim/virtual_camera.h"

#include <algorithm>
#include <stdexcept>

#include "core/clock.h"

namespace penumbra::firmware_sim {

using kiosk::CameraFrame;
using kiosk::GrabStatus;
using kiosk::PixelFormat;

const char* cameraFaultName(CameraFaultKind kind) {
  switch (kind) {
    case CameraFaultKind::kDrop:
      return "drop";
    case CameraFaultKind::kLate:
      return "late";
    case CameraFaultKind::kDuplicate:
      return "duplicate";
    case CameraFaultKind::kWrongSize:
      return "wrong_size";
    case CameraFaultKind::kWrongFormat:
      return "wrong_format";
    case CameraFaultKind::kDisconnect:
      return "disconnect";
  }
  return "unknown";
}

VirtualCamera::VirtualCamera(std::vector<uint8_t> still, uint32_t width, uint32_t height,
                             CameraScript script)
    : VirtualCamera(std::vector<std::vector<uint8_t>>{std::move(still)}, width, height,
                    std::move(script)) {}

VirtualCamera::VirtualCamera(std::vector<std::vector<uint8_t>> frames, uint32_t width,
                             uint32_t height, CameraScript script)
    : frames_(std::move(frames)), width_(width), height_(height), script_(std::move(script)) {
  if (frames_.empty() || width_ < 2 || height_ < 2 ||
      std::any_of(frames_.begin(), frames_.end(), [&](const std::vector<uint8_t>& f) {
        return f.size() != static_cast<size_t>(width_) * height_ * 4;
      })) {
    throw std::invalid_argument("VirtualCamera: every frame must be RGBA8 width x height");
  }
  if (script_.periodNs <= 0 || script_.transportNs < 0) {
    throw std::invalid_argument("VirtualCamera: period > 0 and transport >= 0 required");
  }
}

bool VirtualCamera::faulted(CameraFaultKind kind, uint64_t k, const CameraFault** which) const {
  for (const CameraFault& f : script_.faults) {
    if (f.kind == kind && k >= f.frame && k - f.frame < f.count) {
      if (which) *which = &f;
      return true;
    }
  }
  return false;
}

bool VirtualCamera::disconnectedAt(int64_t nowNs) const {
  for (const CameraFault& f : script_.faults) {
    if (f.kind != CameraFaultKind::kDisconnect) continue;
    const int64_t from = static_cast<int64_t>(f.frame) * script_.periodNs;
    const int64_t to = static_cast<int64_t>(f.frame + f.count) * script_.periodNs;
    if (nowNs >= from && nowNs < to) return true;
  }
  return false;
}

int64_t VirtualCamera::arrivalNs(uint64_t k) const {
  if (faulted(CameraFaultKind::kDrop, k)) return -1;
  // Frames captured while the camera is unplugged never arrive.
  if (disconnectedAt(static_cast<int64_t>(k) * script_.periodNs)) return -1;
  const CameraFault* late = nullptr;
  const int64_t delay = faulted(CameraFaultKind::kLate, k, &late) ? late->delayNs : 0;
  return static_cast<int64_t>(k) * script_.periodNs + script_.transportNs + delay;
}

// The walking person: a body and a head, bottom on the lower third of the frame.
VirtualCamera::PersonShape VirtualCamera::personShape(uint64_t k) const {
  PersonShape p;
  if (script_.personTo > script_.personFrom && k >= script_.personFrom && k < script_.personTo) {
    const int64_t w = script_.personWidth, h = script_.personHeight;
    const int64_t span = static_cast<int64_t>(width_) + w;
    const int64_t t = static_cast<int64_t>(k - script_.personFrom);
    const int64_t n = static_cast<int64_t>(script_.personTo - script_.personFrom);
    p.px0 = -w + span * t / n;
    p.px1 = p.px0 + w - 1;
    p.bottom = static_cast<int64_t>(height_) * 9 / 10;
    p.headTop = p.bottom - h;
    p.bodyTop = p.headTop + w / 2 + 4;
    p.hx0 = p.px0 + w / 4;
    p.hx1 = p.px1 - w / 4;
  }
  return p;
}

bool VirtualCamera::personCovers(uint64_t k, uint32_t x, uint32_t y) const {
  return personShape(k).covers(x, y);
}

void VirtualCamera::render(uint64_t k, CameraFrame& out) const {
  out.width = width_;
  out.height = height_;
  out.stride = width_ * 4;
  out.format = PixelFormat::kXrgb8888;
  out.sequence = k + 1;
  out.captureNs = static_cast<int64_t>(k) * script_.periodNs;
  out.data.resize(static_cast<size_t>(out.stride) * height_);

  // Exposure drift: a triangle wave between 1 − a and 1 + a, gain in ‰.
  int64_t gain = 1000;
  if (script_.driftPeriodFrames > 0 && script_.driftPermille > 0) {
    const int64_t p = script_.driftPeriodFrames;
    const int64_t phase = static_cast<int64_t>(k % static_cast<uint64_t>(p));
    const int64_t tri = phase < p / 2 ? 4 * phase - p : 3 * p - 4 * phase;  // in [-p, p]
    gain = 1000 + static_cast<int64_t>(script_.driftPermille) * tri / p;
  }
  const PersonShape person = personShape(k);
  const std::vector<uint8_t>& filmed = frames_[k % frames_.size()];
  for (uint32_t y = 0; y < height_; ++y) {
    const uint8_t* src = filmed.data() + static_cast<size_t>(y) * width_ * 4;
    uint8_t* dst = out.data.data() + static_cast<size_t>(y) * out.stride;
    for (uint32_t x = 0; x < width_; ++x, src += 4, dst += 4) {
      if (person.covers(x, y)) {
        dst[0] = 52, dst[1] = 40, dst[2] = 36, dst[3] = 255;  // B, G, R, X: dark clothes
        continue;
      }
      for (int c = 0; c < 3; ++c) {
        const int64_t v = src[2 - c] * gain / 1000;  // XRGB8888 bytes are B, G, R, X
        dst[c] = static_cast<uint8_t>(v > 255 ? 255 : v);
      }
      dst[3] = 255;
    }
  }
}

void VirtualCamera::timedRender(uint64_t k, CameraFrame& out) {
  core::Stopwatch watch;
  render(k, out);
  renderNs_ += watch.lapNs();
}

int64_t VirtualCamera::takeRenderNs() {
  const int64_t ns = renderNs_;
  renderNs_ = 0;
  return ns;
}

GrabStatus VirtualCamera::grab(int64_t nowNs, CameraFrame& out) {
  if (!open_) return GrabStatus::kDisconnected;
  if (disconnectedAt(nowNs)) {
    open_ = false;
    return GrabStatus::kDisconnected;
  }
  if (duplicatePending_) {
    // The driver hands the same buffer over a second time.
    duplicatePending_ = false;
    timedRender(lastDelivered_, out);
    return GrabStatus::kFrame;
  }
  // The newest frame that has arrived and is newer than the last one delivered. Late frames
  // can arrive after newer ones: once a newer frame was delivered they are stale and skipped.
  if (nowNs < script_.transportNs) return GrabStatus::kNoFrame;
  const uint64_t newest = static_cast<uint64_t>(nowNs / script_.periodNs);
  const uint64_t oldest = delivered_ ? lastDelivered_ + 1 : 0;
  for (uint64_t k = newest + 1; k-- > oldest;) {
    const int64_t at = arrivalNs(k);
    if (at < 0 || at > nowNs) continue;
    timedRender(k, out);
    if (faulted(CameraFaultKind::kWrongSize, k)) {
      // A mode switch behind our back: half the size.
      out.width = width_ / 2;
      out.height = height_ / 2;
      out.stride = out.width * 4;
      out.data.resize(static_cast<size_t>(out.stride) * out.height);
    }
    if (faulted(CameraFaultKind::kWrongFormat, k)) out.format = PixelFormat::kYuyv;
    delivered_ = true;
    lastDelivered_ = k;
    duplicatePending_ = faulted(CameraFaultKind::kDuplicate, k);
    return GrabStatus::kFrame;
  }
  return GrabStatus::kNoFrame;
}

bool VirtualCamera::reopen(int64_t nowNs) {
  if (disconnectedAt(nowNs)) return false;
  open_ = true;
  return true;
}

std::string VirtualCamera::describe() const {
  return "simulated camera " + std::to_string(width_) + "x" + std::to_string(height_) +
         " XRGB8888 at " + std::to_string(1'000'000'000'000 / script_.periodNs / 1000) + "." +
         std::to_string(1'000'000'000'000 / script_.periodNs % 1000 / 100) + " fps, " +
         (frames_.size() > 1 ? std::to_string(frames_.size()) + " frames of footage, " : "") +
         std::to_string(script_.faults.size()) + " scripted faults";
}

}  // namespace penumbra::firmware_sim
