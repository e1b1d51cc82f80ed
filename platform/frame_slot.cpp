#include "platform/frame_slot.h"

#include <utility>

namespace penumbra::platform {

bool FrameSlot::put(kiosk::CameraFrame& frame) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) return false;
    if (full_) ++overwritten_;
    std::swap(frame_, frame);
    full_ = true;
  }
  ready_.notify_one();
  return true;
}

bool FrameSlot::take(kiosk::CameraFrame& out) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!full_) return false;
  std::swap(frame_, out);
  full_ = false;
  return true;
}

bool FrameSlot::waitAndTake(kiosk::CameraFrame& out, std::chrono::nanoseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait_for(lock, timeout, [&] { return full_ || closed_; });
  if (!full_) return false;
  std::swap(frame_, out);
  full_ = false;
  return true;
}

void FrameSlot::close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  ready_.notify_all();
}

void FrameSlot::reopen() {
  std::lock_guard<std::mutex> lock(mutex_);
  closed_ = false;
}

bool FrameSlot::closed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return closed_;
}

uint64_t FrameSlot::overwritten() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return overwritten_;
}

}  // namespace penumbra::platform
