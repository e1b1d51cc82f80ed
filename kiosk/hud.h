// The kiosk's head-up display: a few lines of text drawn into the RGBA8 frame with a tiny
// built-in 5×7 bitmap font (no SDL_ttf, no system fonts), integers only, so the simulator's
// frame hashes include it and stay bit-exact on every machine.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::kiosk {

struct Rgb {
  uint8_t r, g, b;
};

// Draws `text` with its top-left corner at (x, y), each font pixel a scale×scale block.
// Lower-case letters are drawn as upper case; characters without a glyph as a box. Pixels
// outside the frame are skipped. Returns the x just past the text.
int drawText(std::span<uint8_t> rgba, uint32_t width, uint32_t height, int x, int y,
             std::string_view text, Rgb colour, int scale = 2);

// Halves the colour of a rectangle (a dark band behind text), clipped to the frame.
void darkenRect(std::span<uint8_t> rgba, uint32_t width, uint32_t height, int x, int y, int w,
                int h);

struct HudInfo {
  uint32_t fpsTenths = 0;  // frames per second × 10, over the last second
  uint32_t passes = 0;
  uint32_t shadowMapSize = 0;
  std::string product;
  std::string mode;                   // "FAST", "QUALITY", "ATTRACT ..."
  std::vector<std::string> warnings;  // drawn in red along the bottom, one per line
};

// Top band: "30.0 FPS  24 PASSES  CHAIR  FAST"; bottom: the warnings.
void drawHud(std::span<uint8_t> rgba, uint32_t width, uint32_t height, const HudInfo& info);

}  // namespace penumbra::kiosk
