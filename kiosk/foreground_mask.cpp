#include "kiosk/foreground_mask.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace penumbra::kiosk {
namespace {

// Rec. 709 luma in 8.8 weights summing to 256 (54 + 183 + 19), rounded.
uint32_t luma(const uint8_t* p) {
  return (54u * p[0] + 183u * p[1] + 19u * p[2] + 128u) >> 8;
}

// out[x] = max of in[x - r .. x + r] over one line of `n` values `step` apart.
void maxLine(const uint8_t* in, uint8_t* out, size_t n, size_t step, int r) {
  for (size_t i = 0; i < n; ++i) {
    const size_t lo = i >= size_t(r) ? i - size_t(r) : 0;
    const size_t hi = std::min(n - 1, i + size_t(r));
    uint8_t m = 0;
    for (size_t k = lo; k <= hi && m == 0; ++k) m = in[k * step];
    out[i * step] = m;
  }
}

}  // namespace

ForegroundMask::ForegroundMask(std::span<const uint8_t> emptyRoom, uint32_t width, uint32_t height,
                               const ForegroundOptions& options)
    : emptyRoom_(emptyRoom.begin(), emptyRoom.end()),
      width_(width),
      height_(height),
      options_(options) {
  if (width == 0 || height == 0 || emptyRoom.size() != size_t{width} * height * 4) {
    throw std::invalid_argument("foreground mask: the empty room must be RGBA8 of the view's size");
  }
  if (!(options.release >= 0 && options.release <= options.threshold && options.threshold <= 255 &&
        options.grow >= 0 && options.grow <= 16)) {
    throw std::invalid_argument(
        "foreground mask: need 0 <= release <= threshold <= 255 and 0 <= grow <= 16 (got " +
        std::to_string(options.release) + ", " + std::to_string(options.threshold) + ", " +
        std::to_string(options.grow) + ")");
  }
  const size_t pixels = size_t{width} * height;
  raw_.assign(pixels, 0);
  mask_.assign(pixels, 0);
  scratch_.assign(pixels, 0);
}

void ForegroundMask::reset() {
  std::fill(raw_.begin(), raw_.end(), 0);
  std::fill(mask_.begin(), mask_.end(), 0);
}

size_t ForegroundMask::update(std::span<const uint8_t> frame) {
  const size_t w = width_, h = height_, pixels = w * h;
  if (frame.size() != pixels * 4) {
    throw std::invalid_argument("foreground mask: the frame is not RGBA8 of the view's size");
  }
  // 1. The exposure gain: median of the luma ratios on the grid.
  ratios_.clear();
  for (size_t y = kGridStep / 2; y < h; y += kGridStep) {
    for (size_t x = kGridStep / 2; x < w; x += kGridStep) {
      const size_t i = 4 * (y * w + x);
      const uint32_t room = luma(&emptyRoom_[i]);
      if (room < 24 || room > 232) continue;  // clipped or noise-dominated
      ratios_.push_back((luma(&frame[i]) * 256u + room / 2) / room);
    }
  }
  gain256_ = 256;
  if (!ratios_.empty()) {
    const auto middle = ratios_.begin() + std::ptrdiff_t(ratios_.size() / 2);
    std::nth_element(ratios_.begin(), middle, ratios_.end());
    gain256_ = std::clamp(*middle, 64u, 1024u);
  }
  // 2. Differences against the gained photograph, with hysteresis on the last frame's
  // filtered mask (raw_ holds it from step 3 of the last call).
  const int threshold = options_.threshold, release = options_.release;
  for (size_t i = 0; i < pixels; ++i) {
    int d = 0;
    for (size_t c = 0; c < 3; ++c) {
      const int room = int(std::min<uint32_t>((emptyRoom_[4 * i + c] * gain256_ + 128) >> 8, 255));
      d = std::max(d, std::abs(int(frame[4 * i + c]) - room));
    }
    scratch_[i] = d > threshold || (raw_[i] != 0 && d > release) ? 1 : 0;
  }
  // 3. Majority of the 3x3 neighbourhood (at least 5 of 9; pixels outside count as
  // background), kept in raw_ for the next frame's hysteresis; then the growth into mask_.
  column_.resize(w + 2);  // column sums of three rows, one zero on each side
  for (size_t y = 0; y < h; ++y) {
    const uint8_t* above = y > 0 ? &scratch_[(y - 1) * w] : nullptr;
    const uint8_t* row = &scratch_[y * w];
    const uint8_t* below = y + 1 < h ? &scratch_[(y + 1) * w] : nullptr;
    for (size_t x = 0; x < w; ++x) {
      column_[x + 1] =
          static_cast<uint8_t>(row[x] + (above ? above[x] : 0) + (below ? below[x] : 0));
    }
    for (size_t x = 0; x < w; ++x) {
      raw_[y * w + x] = column_[x] + column_[x + 1] + column_[x + 2] >= 5 ? 1 : 0;
    }
  }
  for (size_t y = 0; y < h; ++y) maxLine(&raw_[y * w], &scratch_[y * w], w, 1, options_.grow);
  for (size_t x = 0; x < w; ++x) maxLine(&scratch_[x], &mask_[x], h, w, options_.grow);
  size_t count = 0;
  for (uint8_t m : mask_) count += m;
  return count;
}

void ForegroundMask::applyTo(std::span<uint8_t> rendered, std::span<const uint8_t> frame) const {
  if (rendered.size() != mask_.size() * 4 || frame.size() != mask_.size() * 4) {
    throw std::invalid_argument("foreground mask: images must be RGBA8 of the view's size");
  }
  for (size_t i = 0; i < mask_.size(); ++i) {
    if (mask_[i] != 0) std::copy_n(&frame[4 * i], 4, &rendered[4 * i]);
  }
}

}  // namespace penumbra::kiosk
