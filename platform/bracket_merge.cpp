#include "platform/bracket_merge.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra::platform {

BracketMerge::BracketMerge(const ChannelResponse& response, std::span<const double> exposuresMs,
                           double exposureScale) {
  if (exposuresMs.empty()) throw std::invalid_argument("bracket merge: no exposure");
  for (size_t j = 0; j < exposuresMs.size(); ++j) {
    if (j > 0 && !(exposuresMs[j] > exposuresMs[j - 1])) {
      throw std::invalid_argument("bracket merge: exposure " + std::to_string(j) +
                                  " is not longer than the one before");
    }
    radiance_.push_back(radianceTables(response, exposuresMs[j], exposureScale));
  }
  for (int z = 0; z < 256; ++z) weight_[size_t(z)] = hatWeight(z);
  for (const ChannelTables& r : radiance_) {
    ChannelTables& w = weightedRadiance_.emplace_back();
    for (size_t c = 0; c < 3; ++c)
      for (size_t z = 0; z < 256; ++z) w[c][z] = weight_[z] * r[c][z];
  }
}

size_t BracketMerge::merge(std::span<const uint8_t* const> frames, std::span<const size_t> strides,
                           uint32_t width, uint32_t height, core::ImageF& out) const {
  const size_t n = radiance_.size();
  if (frames.size() != n || strides.size() != n) {
    throw std::invalid_argument("bracket merge: " + std::to_string(frames.size()) + " frames for " +
                                std::to_string(n) + " exposures");
  }
  if (out.width != width || out.height != height) out = core::ImageF(width, height);
  const ChannelTables& shortest = radiance_.front();
  const ChannelTables& longest = radiance_.back();
  size_t saturated = 0;
  float* o = out.pixels.data();
  std::vector<const uint8_t*> rows(n);  // this image row of each exposure
  for (uint32_t y = 0; y < height; ++y) {
    for (size_t j = 0; j < n; ++j) rows[j] = frames[j] + strides[j] * y;
    for (uint32_t x = 0; x < width; ++x, o += 3) {
      const size_t at = size_t(x) * 3;
      bool clippedBright = false;
      for (size_t c = 0; c < 3; ++c) {
        const size_t byte = at + 2 - c;  // BGR in, RGB out
        // Σ in exposure order, shortest first: the same additions on every machine.
        float num = 0, den = 0;
        for (size_t j = 0; j < n; ++j) {
          const uint8_t z = rows[j][byte];
          num += weightedRadiance_[j][c][z];
          den += weight_[z];
        }
        if (den > 0) {
          o[c] = num / den;  // den is a sum of integers ≤ 127 · n: exact
        } else {
          const uint8_t first = rows[0][byte];
          o[c] = first == 255 ? shortest[c][255] : longest[c][rows[n - 1][byte]];
          clippedBright |= first == 255;
        }
      }
      saturated += size_t(clippedBright);
    }
  }
  return saturated;
}

}  // namespace penumbra::platform
