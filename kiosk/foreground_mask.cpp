#include "kiosk/foreground_mask.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace penumbra::kiosk {
namespace {

// Rec. 709 luma in 8.8 weights summing to 256 (54 + 183 + 19), rounded.
uint32_t luma(const uint8_t* p) {
  return (54u * p[0] + 183u * p[1] + 19u * p[2] + 128u) >> 8;
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
  return update(frame, 0, height_);
}

size_t ForegroundMask::showInFront(std::span<uint8_t> rendered, std::span<const uint8_t> frame) {
  const size_t w = width_, h = height_, rowBytes = 4 * w;
  if (rendered.size() != h * rowBytes || frame.size() != h * rowBytes) {
    throw std::invalid_argument("foreground mask: images must be RGBA8 of the view's size");
  }
  // Only rows where the product or its shadow changed a pixel can be affected; the mask
  // there needs the difference flags of 1 + grow rows around them.
  size_t first = h, last = 0;
  for (size_t y = 0; y < h; ++y) {
    if (std::memcmp(&rendered[y * rowBytes], &frame[y * rowBytes], rowBytes) != 0) {
      first = std::min(first, y);
      last = y + 1;
    }
  }
  if (first >= last) {
    update(frame, 0, 0);  // the gain, and no history
    return 0;
  }
  const size_t margin = 1 + size_t(options_.grow);
  update(frame, first >= margin ? first - margin : 0, std::min(h, last + margin));
  size_t shown = 0;
  for (size_t y = first; y < last; ++y) {
    for (size_t x = 0; x < w; ++x) {
      const size_t i = y * w + x;
      if (mask_[i] == 0) continue;
      std::copy_n(&frame[4 * i], 4, &rendered[4 * i]);
      ++shown;
    }
  }
  return shown;
}

size_t ForegroundMask::update(std::span<const uint8_t> frame, size_t rowBegin, size_t rowEnd) {
  const size_t w = width_, h = height_, pixels = w * h;
  if (frame.size() != pixels * 4) {
    throw std::invalid_argument("foreground mask: the frame is not RGBA8 of the view's size");
  }
  rowEnd = std::min(rowEnd, h);
  rowBegin = std::min(rowBegin, rowEnd);
  // Outside the rows: no flags, no history, no mask.
  for (auto* plane : {&scratch_, &raw_, &mask_}) {
    std::fill(plane->begin(), plane->begin() + std::ptrdiff_t(rowBegin * w), uint8_t{0});
    std::fill(plane->begin() + std::ptrdiff_t(rowEnd * w), plane->end(), uint8_t{0});
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
  // The loops below run over every pixel of the rows, every frame; each is written over
  // restrict-qualified row pointers with no branch, so that the compiler vectorizes it
  // (uint8_t pointers may otherwise alias anything, and the scalar loops cost 1.3 ms a frame).
  differences(frame, rowBegin, rowEnd);
  majority(rowBegin, rowEnd);
  grow(rowBegin, rowEnd);
  size_t count = 0;
  for (size_t i = rowBegin * w; i < rowEnd * w; ++i) count += mask_[i];
  return count;
}

// 2. Differences against the gained photograph, with hysteresis on the last frame's filtered
// mask (raw_ holds it from step 3 of the last call). Per byte first (the alpha byte too,
// ignored after), |frame - min((room * gain + 128) >> 8, 255)|: all four channels in one
// loop of bytes. Then per pixel the largest of the three colour bytes against the limit.
void ForegroundMask::differences(std::span<const uint8_t> frame, size_t rowBegin, size_t rowEnd) {
  const size_t w = width_;
  const int threshold = options_.threshold, release = options_.release;
  // In 16-bit lanes: with gain = 256 whole + part (whole <= 4, part <= 255),
  //   (room * gain + 128) >> 8 = room * whole + ((room * part + 128) >> 8)
  // exactly, as room * whole * 256 is a multiple of 256; and room * part + 128 <= 65153,
  // room * whole <= 1020 both fit 16 bits, where the 18-bit product would not.
  const auto whole = static_cast<uint16_t>(gain256_ >> 8);
  const auto part = static_cast<uint16_t>(gain256_ & 255u);
  rowDifference_.resize(4 * w);
  uint8_t* __restrict diff = rowDifference_.data();
  for (size_t y = rowBegin; y < rowEnd; ++y) {
    const uint8_t* __restrict room = &emptyRoom_[4 * w * y];
    const uint8_t* __restrict seen = &frame[4 * w * y];
    for (size_t j = 0; j < 4 * w; ++j) {
      const auto low = static_cast<uint16_t>(static_cast<uint16_t>(room[j] * part + 128u) >> 8);
      const auto gained = static_cast<uint16_t>(room[j] * whole + low);
      const uint16_t expected = std::min(gained, uint16_t{255});
      const uint16_t v = seen[j];
      diff[j] = static_cast<uint8_t>(v > expected ? v - expected : expected - v);
    }
    const uint8_t* __restrict last = &raw_[w * y];
    uint8_t* __restrict flags = &scratch_[w * y];
    for (size_t x = 0; x < w; ++x) {
      const int d = std::max({diff[4 * x], diff[4 * x + 1], diff[4 * x + 2]});
      const int limit = last[x] != 0 ? release : threshold;
      flags[x] = static_cast<uint8_t>(d > limit);
    }
  }
}

// 3. Majority of the 3x3 neighbourhood (at least 5 of 9; pixels outside count as
// background), kept in raw_ for the next frame's hysteresis: column sums of three rows
// (a zero row beyond the edges), then sums of three columns.
void ForegroundMask::majority(size_t rowBegin, size_t rowEnd) {
  const size_t w = width_, h = height_;
  zeroRow_.assign(w, 0);
  column_.assign(w + 2, 0);  // one zero column on each side
  for (size_t y = rowBegin; y < rowEnd; ++y) {
    const uint8_t* __restrict above = y > 0 ? &scratch_[(y - 1) * w] : zeroRow_.data();
    const uint8_t* __restrict row = &scratch_[y * w];
    const uint8_t* __restrict below = y + 1 < h ? &scratch_[(y + 1) * w] : zeroRow_.data();
    uint8_t* __restrict sums = column_.data();
    for (size_t x = 0; x < w; ++x) {
      sums[x + 1] = static_cast<uint8_t>(above[x] + row[x] + below[x]);
    }
    uint8_t* __restrict out = &raw_[y * w];
    for (size_t x = 0; x < w; ++x) {
      out[x] = static_cast<uint8_t>(sums[x] + sums[x + 1] + sums[x + 2] >= 5);
    }
  }
}

// Growth by `grow` pixels: the maximum over a (2 grow + 1)^2 square, rows first (each row
// padded with `grow` zeros on both sides), then rows of those maxima ORed together.
void ForegroundMask::grow(size_t rowBegin, size_t rowEnd) {
  const size_t w = width_, h = height_, r = size_t(options_.grow);
  column_.assign(w + 2 * r, 0);
  for (size_t y = rowBegin; y < rowEnd; ++y) {
    std::copy_n(&raw_[y * w], w, column_.data() + r);
    const uint8_t* __restrict padded = column_.data();
    uint8_t* __restrict out = &scratch_[y * w];
    std::fill_n(out, w, uint8_t{0});
    for (size_t k = 0; k <= 2 * r; ++k) {
      for (size_t x = 0; x < w; ++x) out[x] |= padded[x + k];
    }
  }
  for (size_t y = rowBegin; y < rowEnd; ++y) {
    uint8_t* __restrict out = &mask_[y * w];
    std::fill_n(out, w, uint8_t{0});
    const size_t lo = y >= r ? y - r : 0, hi = std::min(h - 1, y + r);
    for (size_t yy = lo; yy <= hi; ++yy) {
      const uint8_t* __restrict in = &scratch_[yy * w];
      for (size_t x = 0; x < w; ++x) out[x] |= in[x];
    }
  }
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
