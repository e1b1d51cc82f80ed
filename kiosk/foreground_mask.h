// Real things in front of the product (issue 15 item 5): a visitor walking between the
// camera and the synthetic product must hide it and its shadow, as a real chair would be
// hidden. The kiosk knows the empty room — the calibrated background photograph of the
// bundle — so whatever the camera shows that the empty room does not is taken as standing
// in front, and the camera's own pixels are shown there instead of the composited frame.
//
// Per camera frame:
//   1. Exposure: the frame may be uniformly brighter or darker than the photograph (auto
//      gain left on, lamps dimming; firmware-sim's drift). Its gain g is the median, over a
//      grid of pixels every kGridStep in x and y whose photograph luma is away from black and
//      white, of luma(frame) / luma(photograph) in 8.8 fixed point. A person covering less
//      than half of the grid does not move the median.
//   2. Difference: per pixel, the largest channel difference between the frame and the
//      photograph times g. Foreground where it exceeds `threshold`, or `release` for a pixel
//      that was foreground in the last frame (hysteresis: a pixel near the threshold does
//      not blink from frame to frame).
//   3. Shape: a pixel stays foreground when at least 5 of its 3x3 neighbourhood are (sensor
//      noise and single-pixel speckle go), then the mask grows by `grow` pixels, so that the
//      edges of a person — blurred, and where the difference fades — are covered too.
// All integer arithmetic in a fixed order: the mask, and the frame it touches, are the same
// bytes on every machine and thread count.
//
// A limit, stated: without depth the mask cannot tell a visitor in front of the product
// from one behind it; both are shown in front. At a kiosk the visitor is nearly always the
// one in front.
//
// Cost: a few integer operations per pixel and channel, in branch-free loops over
// restrict-qualified rows that the compiler vectorizes (16-bit lanes for the gained
// photograph; foreground_mask.cpp proves the bound).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace penumbra::kiosk {

struct ForegroundOptions {
  int threshold = 32;  // levels of the largest channel difference that make foreground
  int release = 20;    // levels below which a foreground pixel becomes background again
  int grow = 2;        // pixels the mask is dilated by
};

class ForegroundMask {
 public:
  static constexpr uint32_t kGridStep = 8;

  // `emptyRoom`: RGBA8 of width x height, the photograph the bundle was calibrated on.
  // Throws std::invalid_argument for a wrong size or options out of order
  // (0 <= release <= threshold <= 255, 0 <= grow <= 16).
  ForegroundMask(std::span<const uint8_t> emptyRoom, uint32_t width, uint32_t height,
                 const ForegroundOptions& options = {});

  // The mask of one camera frame (RGBA8, the same size); returns its foreground pixels.
  size_t update(std::span<const uint8_t> frame);
  // Where the mask is set, `rendered` takes `frame`'s pixel: the real thing stays in front.
  void applyTo(std::span<uint8_t> rendered, std::span<const uint8_t> frame) const;
  // update() and applyTo() where they can matter: only the rows in which `rendered` (the
  // composited frame) differs from `frame` (the camera frame it was composited over) hold
  // product or shadow, so the mask is computed for those rows and the 1 + grow rows around
  // them (elsewhere it and its history are empty). Returns the pixels taken from `frame`.
  size_t showInFront(std::span<uint8_t> rendered, std::span<const uint8_t> frame);

  // 1 per foreground pixel, row by row.
  std::span<const uint8_t> mask() const { return mask_; }
  // The last frame's exposure gain against the photograph, in 1/256.
  uint32_t gain256() const { return gain256_; }
  // Drops the history (hysteresis), e.g. after the camera came back from an outage.
  void reset();

 private:
  size_t update(std::span<const uint8_t> frame, size_t rowBegin, size_t rowEnd);
  void differences(std::span<const uint8_t> frame, size_t rowBegin, size_t rowEnd);
  void majority(size_t rowBegin, size_t rowEnd);
  void grow(size_t rowBegin, size_t rowEnd);
  std::vector<uint8_t> emptyRoom_;
  uint32_t width_, height_;
  ForegroundOptions options_;
  std::vector<uint8_t> raw_, mask_, scratch_, column_, zeroRow_, rowDifference_;
  std::vector<uint32_t> ratios_;
  uint32_t gain256_ = 256;
};

}  // namespace penumbra::kiosk
