// A latest-frame mailbox between a camera's own thread and the kiosk loop (issue 6 §1).
// libcamera completes requests on its internal thread (CameraManager's event loop); the kiosk
// wants only the newest frame when its own frame starts, never a queue of old ones that would
// add latency. One slot: put() replaces a frame the kiosk has not taken yet (counted as
// overwritten: the kiosk was slower than the sensor), take() hands the newest one over.
//
// Both sides swap buffers with the slot instead of copying, so after warm-up no frame is
// allocated: the producer gets back a buffer to fill next, the consumer gives back the one it
// showed last. Everything is under one mutex; a condition variable wakes a waiting consumer.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>

#include "kiosk/frame_source.h"

namespace penumbra::platform {

class FrameSlot {
 public:
  // Producer: moves `frame` into the slot; `frame` comes back holding a recycled buffer (of
  // unspecified content). Returns false, and leaves `frame` alone, once the slot is closed.
  bool put(kiosk::CameraFrame& frame);

  // Consumer: the newest frame not taken yet, swapped into `out` (whose old buffer the slot
  // keeps for the producer). False when nothing new is waiting.
  bool take(kiosk::CameraFrame& out);
  // As take(), waiting up to `timeout` for a frame; false on timeout or when closed.
  bool waitAndTake(kiosk::CameraFrame& out, std::chrono::nanoseconds timeout);

  // The producer is gone (camera stopped or unplugged): wakes a waiting consumer; put()
  // refuses frames until reopen(). A frame already waiting can still be taken.
  void close();
  void reopen();
  bool closed() const;

  // Frames replaced before the consumer took them (the kiosk dropped them), since creation.
  uint64_t overwritten() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  kiosk::CameraFrame frame_;
  bool full_ = false;
  bool closed_ = false;
  uint64_t overwritten_ = 0;
};

}  // namespace penumbra::platform
