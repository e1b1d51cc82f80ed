// The kiosk screen straight on the kernel's display (DRM/KMS) through libdrm: the frame is
// drawn by the CPU anyway, so all a board needs is a scanout buffer in memory ("dumb buffer")
// and a page flip. No EGL, no GBM, no Mesa driver: SDL2's KMSDRM driver can only present
// through them, and in the board VM they took the libcamera kiosk's peak RSS from 40.6 MB
// (this display) to 117.3 MB (docs/kiosk.md, "Memory").
//
// The frame is scaled to the screen's mode by nearest neighbour, keeping its aspect, centred
// between black bars (a 640x480 frame on a 1920x1080 screen: 1440x1080 at x = 240, each frame
// pixel 2 or 3 screen pixels wide; a bilinear filter would cost the board ~1.5 M pixels of
// four taps a frame).
// Two buffers: the next frame is written into the one not being scanned out, then flipped
// at the next vertical blank; show() waits only for a flip still pending from the frame
// before.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "kiosk/status.h"
#include "platform/hardware.h"

namespace penumbra::platform {

// Where a frame lands on a screen and which frame pixel each screen pixel shows: the
// largest scale that fits, the same in x and y, centred. Pure arithmetic, tested apart.
struct ScreenFit {
  uint32_t x = 0, y = 0, width = 0, height = 0;  // the frame's rectangle on the screen
  std::vector<uint32_t> sourceColumn;            // per screen column of the rectangle
  std::vector<uint32_t> sourceRow;               // per screen row of the rectangle
};
// Throws std::invalid_argument for an empty frame or screen.
ScreenFit fitFrame(uint32_t frameWidth, uint32_t frameHeight, uint32_t screenWidth,
                   uint32_t screenHeight);

// Writes the RGBA8 frame (row 0 at the top) into an XRGB8888 screen buffer of `pitch` bytes
// per row at the fit's rectangle (B, G, R, X in memory on a little-endian CPU, as DRM's
// XRGB8888 is). The bars around it are not touched.
void blitFrame(const uint8_t* rgba, uint32_t frameWidth, const ScreenFit& fit, uint8_t* screen,
               uint32_t pitch);

class DrmDisplay final : public kiosk::Display {
 public:
  // `device` empty: the first /dev/dri/card* with a connected connector (a Raspberry Pi's
  // card0 may be the render-only v3d and its screen card1). Takes the connector's preferred
  // mode. Throws HardwareUnavailable naming the device and the reason (no such file, not a
  // DRM device, no connected screen, not allowed to set the mode: another program holds the
  // display).
  DrmDisplay(const std::filesystem::path& device, uint32_t frameWidth, uint32_t frameHeight);
  ~DrmDisplay() override;  // puts back what the screen showed before (the console)
  DrmDisplay(const DrmDisplay&) = delete;
  DrmDisplay& operator=(const DrmDisplay&) = delete;

  // Throws std::invalid_argument for a frame of another size than the one given at
  // construction, std::runtime_error naming the device when the kernel refuses a flip.
  bool show(const uint8_t* rgba, uint32_t width, uint32_t height) override;
  // "DRM /dev/dri/card0 Virtual-1 1280x800" for the log.
  std::string description() const;

  struct Impl;  // the device's state (drm_display.cpp)

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::platform
