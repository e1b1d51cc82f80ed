// A square shadow map (spec §6 step 1) stored with a one-texel border of +inf on every side.
//
// A lookup one texel outside the map then reads "no occluder" by itself, which is what spec
// §7 asks for texels outside [0, size), so the SIMD 2x2 filter needs no per-texel bounds
// test. The allocation also leaves room for three rows and a SIMD vector (16 floats) past
// the last texel: the small-triangle kernel reads and rewrites unchanged blocks of up to
// four rows there.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

namespace penumbra::raster {

class ShadowMap {
 public:
  // Every texel (and the border) to +inf, at a new size.
  void reset(int32_t size) {
    size_ = size;
    texels_.assign(size_t(stride()) * size_t(stride() + kSlackRows) + kVectorSlack, kInfinity);
    blocks_.assign(size_t(blocksPerRow()) * size_t(blocksPerRow()), 0);
    lastMarked_ = {};
  }
  // Coarse occupancy for the mask sweep: block (bx, by) covers the texels (i, j) with
  // (i + 8) >> 3 == bx and (j + 8) >> 3 == by (so i = -1, the border, falls in block 0).
  // It is nonzero when some texel of [8bx - 8, 8bx] x [8by - 8, 8by] (the block and the
  // column and row after it) may have been written, i.e. when a lane whose 2x2 PCF
  // footprint starts in the block may see a finite texel. Zero blocks promise +inf texels.
  int32_t blocksPerRow() const { return (size_ + 2 + 7) / 8 + 1; }
  const uint32_t* blocks() const { return blocks_.data(); }
  // Records that texels [x0, x1) x [y0, y1) may have been written (x0 < x1, y0 < y1):
  // lanes with i in [x0 - 1, x1 - 1] and j in [y0 - 1, y1 - 1] reach them.
  // Consecutive occluder triangles are small neighbours that mostly fall in the blocks the
  // previous call marked (still set: only clear() and reset() unmark): those return early.
  void markWritten(int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
    const BlockRect r{(x0 - 1 + 8) >> 3, (y0 - 1 + 8) >> 3, (x1 - 1 + 8) >> 3, (y1 - 1 + 8) >> 3};
    if (r.bx0 >= lastMarked_.bx0 && r.bx1 <= lastMarked_.bx1 && r.by0 >= lastMarked_.by0 &&
        r.by1 <= lastMarked_.by1) {
      return;
    }
    lastMarked_ = r;
    const int32_t bpr = blocksPerRow();
    for (int32_t by = r.by0; by <= r.by1; ++by) {
      for (int32_t bx = r.bx0; bx <= r.bx1; ++bx)
        blocks_[size_t(by) * size_t(bpr) + size_t(bx)] = 1;
    }
  }
  // After the last markWritten of a pass: counts of marked blocks over every rectangle
  // from block (0, 0), so that blocksWritten answers for a rectangle in four reads.
  void sumBlocks() {
    const size_t bpr = size_t(blocksPerRow()), side = bpr + 1;
    blockSums_.assign(side * side, 0);
    for (size_t by = 0; by < bpr; ++by) {
      for (size_t bx = 0; bx < bpr; ++bx) {
        blockSums_[(by + 1) * side + bx + 1] =
            (blocks_[by * bpr + bx] != 0 ? 1 : 0) + blockSums_[by * side + bx + 1] +
            blockSums_[(by + 1) * side + bx] - blockSums_[by * side + bx];
      }
    }
  }
  // False when no lane whose footprint starts at a texel (i, j) with i0 <= i <= i1 and
  // j0 <= j <= j1 (all in [-1, size]) can see a written texel (the block rule above); needs
  // sumBlocks() after the last markWritten.
  bool blocksWritten(int32_t i0, int32_t j0, int32_t i1, int32_t j1) const {
    const size_t side = size_t(blocksPerRow()) + 1;
    const size_t bx0 = size_t((i0 + 8) >> 3), by0 = size_t((j0 + 8) >> 3);
    const size_t bx1 = size_t((i1 + 8) >> 3) + 1, by1 = size_t((j1 + 8) >> 3) + 1;
    return blockSums_[by1 * side + bx1] - blockSums_[by0 * side + bx1] -
               blockSums_[by1 * side + bx0] + blockSums_[by0 * side + bx0] !=
           0;
  }
  // Texels [x0, x1) x [y0, y1) back to +inf, and every block to "not written".
  // Copies from a row of +inf: g++ -O2 leaves std::fill of a float value as a scalar loop
  // (a 256x256 map is then 65,536 single stores per pass); memcpy runs in vectors.
  void clear(int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
    std::fill(blocks_.begin(), blocks_.end(), 0u);
    lastMarked_ = {};
    if (x0 >= x1) return;
    if (infinities_.size() < size_t(x1 - x0)) infinities_.assign(size_t(stride()), kInfinity);
    for (int32_t y = y0; y < y1; ++y) {
      std::memcpy(origin() + rowOffset(y) + x0, infinities_.data(),
                  sizeof(float) * size_t(x1 - x0));
    }
  }
  int32_t size() const { return size_; }
  int32_t stride() const { return size_ + 2; }
  // Texel (0, 0); texel (i, j) is at origin()[j * stride() + i] for -1 <= i, j <= size.
  float* origin() { return texels_.data() + stride() + 1; }
  const float* origin() const { return texels_.data() + stride() + 1; }

 private:
  static constexpr float kInfinity = std::numeric_limits<float>::infinity();
  static constexpr size_t kSlackRows = 3;
  static constexpr size_t kVectorSlack = 16;
  std::ptrdiff_t rowOffset(int32_t y) const { return std::ptrdiff_t(y) * stride(); }
  std::vector<float> texels_;
  std::vector<float> infinities_;  // a row of +inf to clear from
  std::vector<uint32_t> blocks_;
  std::vector<int32_t> blockSums_;  // sumBlocks(): (bpr + 1)^2 rectangle counts
  struct BlockRect {
    int32_t bx0 = 0, by0 = 0, bx1 = -1, by1 = -1;  // inclusive; empty by default
  };
  BlockRect lastMarked_;  // the blocks the last markWritten set
  int32_t size_ = 0;
};

}  // namespace penumbra::raster
