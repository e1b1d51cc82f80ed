// A square shadow map (spec §6 step 1) stored with a one-texel border of +inf on every side.
//
// A lookup one texel outside the map then reads "no occluder" by itself, which is what spec
// §7 asks for texels outside [0, size), so the SIMD 2x2 filter needs no per-texel bounds
// test. The allocation also leaves room for three rows and a SIMD vector (16 floats) past
// the last texel: the small-triangle kernel reads and rewrites unchanged blocks of up to
// four rows there.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "raster/frame_trace.h"

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
  // Area-light penumbrae (spec §7): after the last texel of a pass is written, given a
  // rectangle [x0, x1) x [y0, y1) holding every written texel (widened here to even bounds,
  // so that it is whole blocker cells), the counts N(i, j) of written (finite) texels left of
  // column i and above row j for x0 <= i <= x1, y0 <= j <= y1, the blocker cells' sums
  // below, and the nearest and farthest written depths. N is 0 on the rectangle's top and
  // left edges and constant past its right and bottom ones, so lookups clamp to it:
  // coverage()[(j - y0) * coverageStride() + (i - x0)] is N(i, j), with one more column and
  // row repeating the last (a weight-0 neighbour may be read there).
  //
  // Spec §7's blocker search reads cells of kBlockerCell x kBlockerCell texels, cell (a, b)
  // holding texels 2a, 2a + 1 x 2b, 2b + 1: the rectangle's cells are [x0 / 2, x1 / 2) x
  // [y0 / 2, y1 / 2). For a in [0, (x1 - x0) / 2] and b in [0, (y1 - y0) / 2]: the written
  // texels of the rectangle's first a cell columns and b cell rows, and the sum of their
  // quantized depths trunc(kDepthQuantum depth) (modulo 2^32: a box's sum is exact below
  // 2^32), interleaved at blockers()[2 (b blockerStride() + a)] (count, then sum); 0 on the
  // top and left edges, one more column and row repeating the last.
  void sumCoverage(int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
    static_assert(kBlockerCell == 2, "cells are texel pairs of rows and columns");
    // Sizes are multiples of 16, so the even bounds stay in the map.
    x0 = std::clamp(x0 & ~1, 0, size_);
    y0 = std::clamp(y0 & ~1, 0, size_);
    x1 = std::clamp((x1 + 1) & ~1, x0, size_);
    y1 = std::clamp((y1 + 1) & ~1, y0, size_);
    coverageRect_ = {x0, y0, x1, y1};
    const int32_t w = x1 - x0, h = y1 - y0, cs = w + 2, cw = w / 2;
    const size_t bs = size_t(cw) + 2;
    coverage_.resize(size_t(cs) * size_t(h + 2) + 8);         // + the last segment's overrun
    std::fill(coverage_.begin(), coverage_.begin() + cs, 0);  // N(i, y0) = 0
    blockers_.resize(2 * bs * (size_t(h / 2) + 2));
    std::fill(blockers_.begin(), blockers_.begin() + ptrdiff_t(2 * bs), 0u);
    // Each row in loops the compiler vectorizes: written flags, quantized depths and the
    // nearest and farthest depth, then the row above plus the row's running count. Written
    // depths lie in [0, 1], where a float's bits order as an int32's, and an integer max
    // vectorizes where a float one (with its NaN rules) does not; 16 running extrema, one per
    // lane of a 16-texel step, are independent chains (one chain would wait on its own
    // latency every step). The running count needs a scalar chain only across segments of 8
    // texels neither all written nor all unwritten (the occluder's outline); the others add
    // 0 or 1, 2, ..., 8 to it. The cells add texel pairs into a row of cells, summed along
    // it every second row: one chain per cell, not per texel.
    std::array<int32_t, 16> farthestOf{};
    std::array<int32_t, 16> nearestOf;
    nearestOf.fill(kOneBits);
    const int32_t segments = (w + 7) / 8;
    rowCounts_.resize(size_t(segments) * 8 + 16);
    rowDepths_.resize(size_t(w) + 16);
    cellCounts_.assign(size_t(cw) + 1, 0);
    cellSums_.assign(size_t(cw) + 1, 0);
    for (int32_t j = 0; j < h; ++j) {
      const float* row = origin() + rowOffset(y0 + j) + x0;
      int32_t* flags = rowCounts_.data();
      int32_t* depths = rowDepths_.data();
      auto flag = [&](int32_t i, size_t lane) {
        int32_t bits;
        std::memcpy(&bits, &row[i], sizeof bits);
        const int32_t written = bits < kInfinityBits ? -1 : 0;
        flags[i] = -written;
        farthestOf[lane] = std::max(farthestOf[lane], bits & written);
        nearestOf[lane] = std::min(nearestOf[lane], bits | (~written & kOneBits));
        // The product is exact and below 2^31 for depths in [0, 1]; +inf's bits become 0.
        const int32_t kept = bits & written;
        float depth;
        std::memcpy(&depth, &kept, sizeof depth);
        depths[i] = static_cast<int32_t>(depth * kDepthQuantum);
      };
      int32_t i = 0;
      for (; i + 16 <= w; i += 16) {
        for (int32_t k = 0; k < 16; ++k) flag(i + k, size_t(k));
      }
      for (; i < w; ++i) flag(i, 0);
      for (int32_t c = 0; c < cw; ++c) {
        cellCounts_[size_t(c)] += flags[2 * c] + flags[2 * c + 1];
        cellSums_[size_t(c)] += static_cast<uint32_t>(depths[2 * c] + depths[2 * c + 1]);
      }
      if (j % 2 == 1) sumCellRow(j / 2, cw, bs);
      for (i = w; i < segments * 8; ++i) flags[i] = 0;
      const int32_t* above = &coverage_[size_t(j) * size_t(cs)] + 1;
      int32_t* out = &coverage_[size_t(j + 1) * size_t(cs)] + 1;
      out[-1] = 0;
      int32_t run = 0;
      for (int32_t g = 0; g < segments; ++g) {
        const int32_t* f = flags + 8 * g;
        int32_t inSegment = 0;
        for (int32_t k = 0; k < 8; ++k) inSegment += f[k];
        // The last segment may write up to 7 entries past the row's end: into the next rows,
        // which are written again after it, or the 8 entries of slack past the table.
        int32_t* o = out + 8 * g;
        const int32_t* a = above + 8 * g;
        if (inSegment == 0) {
          for (int32_t k = 0; k < 8; ++k) o[k] = a[k] + run;
        } else if (inSegment == 8) {
          for (int32_t k = 0; k < 8; ++k) o[k] = a[k] + run + k + 1;
        } else {
          int32_t r = run;
          for (int32_t k = 0; k < 8; ++k) {
            r += f[k];
            o[k] = a[k] + r;
          }
        }
        run += inSegment;
      }
      out[w] = out[w - 1];  // w = 0: out[-1], the 0 of column x0
    }
    const int32_t farthest = *std::max_element(farthestOf.begin(), farthestOf.end());
    std::memcpy(&farthest_, &farthest, sizeof farthest_);
    const int32_t nearest = *std::min_element(nearestOf.begin(), nearestOf.end());
    std::memcpy(&nearest_, &nearest, sizeof nearest_);
    std::memcpy(&coverage_[size_t(h + 1) * size_t(cs)], &coverage_[size_t(h) * size_t(cs)],
                sizeof(int32_t) * size_t(cs));
    const size_t ch = size_t(h / 2);
    std::copy_n(&blockers_[2 * ch * bs], 2 * bs, &blockers_[2 * (ch + 1) * bs]);
  }
  const int32_t* coverage() const { return coverage_.data(); }
  int32_t coverageStride() const { return coverageRect_.x1 - coverageRect_.x0 + 2; }
  const uint32_t* blockers() const { return blockers_.data(); }
  int32_t blockerStride() const { return (coverageRect_.x1 - coverageRect_.x0) / 2 + 2; }
  struct Rect {
    int32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  };
  const Rect& coverageRect() const { return coverageRect_; }
  float farthest() const { return farthest_; }  // 0 when no texel is written
  float nearest() const { return nearest_; }    // 1 when no texel is written
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
  static constexpr int32_t kInfinityBits = 0x7f800000;  // +inf's bits
  static constexpr int32_t kOneBits = 0x3f800000;       // 1.0f's bits
  static constexpr size_t kSlackRows = 3;
  static constexpr size_t kVectorSlack = 16;
  std::ptrdiff_t rowOffset(int32_t y) const { return std::ptrdiff_t(y) * stride(); }
  // The cells' running sums along cell row b into the table (row b + 1), then a fresh row.
  void sumCellRow(int32_t b, int32_t cw, size_t bs) {
    const uint32_t* above = &blockers_[2 * (size_t(b) * bs + 1)];
    uint32_t* out = &blockers_[2 * (size_t(b + 1) * bs + 1)];
    out[-2] = out[-1] = 0;
    uint32_t count = 0, sum = 0;
    for (int32_t a = 0; a < cw; ++a) {
      count += static_cast<uint32_t>(cellCounts_[size_t(a)]);
      sum += cellSums_[size_t(a)];
      out[2 * a] = above[2 * a] + count;
      out[2 * a + 1] = above[2 * a + 1] + sum;
    }
    out[2 * cw] = out[2 * cw - 2];  // cw = 0: the 0 of column cx0
    out[2 * cw + 1] = out[2 * cw - 1];
    std::fill(cellCounts_.begin(), cellCounts_.end(), 0);
    std::fill(cellSums_.begin(), cellSums_.end(), 0u);
  }
  std::vector<float> texels_;
  std::vector<float> infinities_;  // a row of +inf to clear from
  std::vector<uint32_t> blocks_;
  std::vector<int32_t> blockSums_;  // sumBlocks(): (bpr + 1)^2 rectangle counts
  struct BlockRect {
    int32_t bx0 = 0, by0 = 0, bx1 = -1, by1 = -1;  // inclusive; empty by default
  };
  BlockRect lastMarked_;            // the blocks the last markWritten set
  std::vector<int32_t> coverage_;   // sumCoverage(): N
  std::vector<uint32_t> blockers_;  // and the blocker cells
  std::vector<int32_t> rowCounts_;  // its scratch
  std::vector<int32_t> rowDepths_;
  std::vector<int32_t> cellCounts_;
  std::vector<uint32_t> cellSums_;
  Rect coverageRect_;
  float farthest_ = 0.0f;
  float nearest_ = 1.0f;
  int32_t size_ = 0;
};

}  // namespace penumbra::raster
