#include "reference/shadow_region.h"

#include <algorithm>
#include <cstdlib>
#include <string>

namespace penumbra::reference {

namespace {

void requireSize(std::span<const uint8_t> bytes, size_t channels, uint32_t width, uint32_t height,
                 const std::string& what) {
  if (bytes.size() != size_t(width) * height * channels) {
    throw MetricsError(what + ": " + std::to_string(bytes.size()) + " bytes, a " +
                       std::to_string(width) + "x" + std::to_string(height) + " image needs " +
                       std::to_string(size_t(width) * height * channels));
  }
}

}  // namespace

std::vector<uint8_t> productPixels(std::span<const uint8_t> unshadowed,
                                   std::span<const uint8_t> background, uint32_t width,
                                   uint32_t height) {
  requireSize(unshadowed, 4, width, height, "shadow-free frame");
  requireSize(background, 4, width, height, "background");
  std::vector<uint8_t> product(size_t(width) * height, 0);
  for (size_t i = 0; i < product.size(); ++i) {
    product[i] = unshadowed[4 * i] != background[4 * i] ||
                 unshadowed[4 * i + 1] != background[4 * i + 1] ||
                 unshadowed[4 * i + 2] != background[4 * i + 2];
  }
  return product;
}

core::Image8 shadowRegion(const core::Image8& reference, std::span<const uint8_t> unshadowed,
                          std::span<const uint8_t> background, std::string name) {
  const uint32_t w = reference.width, h = reference.height;
  requireSize(reference.pixels, 3, w, h, reference.name);
  const std::vector<uint8_t> product = productPixels(unshadowed, background, w, h);
  core::Image8 mask(w, h, 1, std::move(name));
  for (size_t i = 0; i < mask.pixels.size(); ++i) {
    if (product[i]) continue;
    for (size_t k = 0; k < 3; ++k) {
      if (reference.pixels[3 * i + k] != unshadowed[4 * i + k]) mask.pixels[i] = 1;
    }
  }
  return mask;
}

void excludeProductPixels(core::Image8& region, std::span<const uint8_t> unshadowed,
                          std::span<const uint8_t> background) {
  requireSize(region.pixels, 1, region.width, region.height, region.name);
  const std::vector<uint8_t> product =
      productPixels(unshadowed, background, region.width, region.height);
  for (size_t i = 0; i < region.pixels.size(); ++i) {
    if (product[i]) region.pixels[i] = 0;
  }
}

ContactErrors contactErrors(const core::Image8& reference, std::span<const uint8_t> frame,
                            std::span<const uint8_t> unshadowed,
                            std::span<const uint8_t> background, const core::Image8& region,
                            int radius) {
  const int w = int(reference.width), h = int(reference.height);
  requireSize(reference.pixels, 3, reference.width, reference.height, reference.name);
  requireSize(frame, 4, reference.width, reference.height, "frame");
  requireSize(region.pixels, 1, reference.width, reference.height, region.name);
  const std::vector<uint8_t> product =
      productPixels(unshadowed, background, reference.width, reference.height);
  std::vector<uint8_t> near(size_t(w) * size_t(h), 0);  // product pixels dilated by radius
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (!product[size_t(y) * size_t(w) + size_t(x)]) continue;
      for (int v = std::max(0, y - radius); v <= std::min(h - 1, y + radius); ++v) {
        for (int u = std::max(0, x - radius); u <= std::min(w - 1, x + radius); ++u) {
          near[size_t(v) * size_t(w) + size_t(u)] = 1;
        }
      }
    }
  }
  ContactErrors e;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t p = size_t(y) * size_t(w) + size_t(x);
      if (product[p]) continue;
      if (!region.pixels[p]) {
        for (size_t c = 0; c < 3; ++c) {
          if (int(unshadowed[4 * p + c]) - int(frame[4 * p + c]) >= 3) {
            ++e.spuriousPixels;
            break;
          }
        }
        continue;
      }
      if (!near[p]) continue;
      ++e.bandPixels;
      for (size_t c = 0; c < 3; ++c) {
        const int d = int(frame[4 * p + c]) - int(reference.pixels[3 * p + c]);
        e.meanAbs += std::abs(d);
        e.meanSigned += d;
      }
    }
  }
  if (e.bandPixels > 0) {
    e.meanAbs /= 3.0 * double(e.bandPixels);
    e.meanSigned /= 3.0 * double(e.bandPixels);
  }
  return e;
}

}  // namespace penumbra::reference
