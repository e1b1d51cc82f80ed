#include "bench/gl_replay/image_compare.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

namespace penumbra::gl {

ImageDiff compareImages(std::span<const uint8_t> a, std::span<const uint8_t> b, uint32_t width,
                        uint32_t height) {
  const size_t n = static_cast<size_t>(width) * height * 4;
  if (a.size() != n || b.size() != n) {
    throw std::invalid_argument("compareImages: buffers are not width*height*4 bytes");
  }
  ImageDiff d;
  d.bytes = n;
  uint64_t equal = 0, sum = 0;
  const auto w = static_cast<int64_t>(width), h = static_cast<int64_t>(height);
  for (int64_t y = 0; y < h; ++y) {
    for (int64_t x = 0; x < w; ++x) {
      bool pixelDiffers = false;
      for (int64_t c = 0; c < 4; ++c) {
        const size_t i = static_cast<size_t>((y * w + x) * 4 + c);
        const int diff = std::abs(int{a[i]} - int{b[i]});
        if (diff == 0) {
          ++equal;
          continue;
        }
        pixelDiffers = true;
        sum += static_cast<uint64_t>(diff);
        d.maxAbsDiff = std::max(d.maxAbsDiff, diff);
        int best = diff;
        for (int64_t dy = -1; dy <= 1 && best > 0; ++dy) {
          for (int64_t dx = -1; dx <= 1 && best > 0; ++dx) {
            const int64_t nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
            const size_t j = static_cast<size_t>((ny * w + nx) * 4 + c);
            best = std::min(best, std::abs(int{a[i]} - int{b[j]}));
          }
        }
        d.maxAbsDiffShiftTolerant = std::max(d.maxAbsDiffShiftTolerant, best);
      }
      if (pixelDiffers) ++d.differingPixels;
    }
  }
  d.identicalByteShare = n == 0 ? 1.0 : static_cast<double>(equal) / static_cast<double>(n);
  d.meanAbsDiff = n == 0 ? 0.0 : static_cast<double>(sum) / static_cast<double>(n);
  return d;
}

}  // namespace penumbra::gl
