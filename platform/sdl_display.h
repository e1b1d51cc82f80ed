// The kiosk screen on SDL2 (design.md §2): full screen on KMSDRM on the board, a window on a
// desktop, or the offscreen driver (tests, headless CI) — chosen by SDL_VIDEODRIVER. The
// frame (HUD already drawn into it) is streamed into one texture per frame.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "kiosk/status.h"
#include "platform/hardware.h"

namespace penumbra::platform {

class SdlDisplay final : public kiosk::Display {
 public:
  // Throws HardwareUnavailable with SDL's reason (no display, no driver).
  SdlDisplay(uint32_t width, uint32_t height, bool fullscreen);
  ~SdlDisplay() override;
  SdlDisplay(const SdlDisplay&) = delete;
  SdlDisplay& operator=(const SdlDisplay&) = delete;

  // False when the window was closed or Escape/Q pressed. Throws std::invalid_argument for
  // a frame of another size than the display's.
  bool show(const uint8_t* rgba, uint32_t width, uint32_t height) override;
  std::string driver() const;
  // SDL's drivers that draw into memory only ("offscreen", "dummy" and its "evdev" variant):
  // SDL falls back to them when no screen answers.
  bool showsNothing() const;
  uint64_t framesShown() const { return shown_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  uint64_t shown_ = 0;
};

}  // namespace penumbra::platform
