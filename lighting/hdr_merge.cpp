#include "lighting/hdr_merge.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra::lighting {

MergeResult mergeExposures(std::span<const Exposure> bracket, const CameraResponse& response) {
  checkBracket(bracket);
  const size_t pixels = size_t(bracket[0].image.width) * size_t(bracket[0].image.height);
  std::vector<double> logDt(bracket.size());
  size_t shortest = 0, longest = 0;
  for (size_t j = 0; j < bracket.size(); ++j) {
    logDt[j] = std::log(bracket[j].seconds);
    if (bracket[j].seconds < bracket[shortest].seconds) shortest = j;
    if (bracket[j].seconds > bracket[longest].seconds) longest = j;
  }
  MergeResult out;
  out.radiance.width = bracket[0].image.width;
  out.radiance.height = bracket[0].image.height;
  out.radiance.pixels.assign(pixels * 3, 0.0f);
  out.minRadiance = std::numeric_limits<double>::infinity();
  out.maxRadiance = 0;
  for (size_t p = 0; p < pixels; ++p) {
    bool bright = false, dark = false;
    for (int c = 0; c < 3; ++c) {
      const std::array<double, 256>& g = response.logExposure[c];
      double num = 0, den = 0;
      for (size_t j = 0; j < bracket.size(); ++j) {  // fixed order: bracket order
        const int z = bracket[j].image.pixels[3 * p + c];
        const double w = hatWeight(z);
        num += w * (g[z] - logDt[j]);
        den += w;
      }
      double e;
      if (den > 0) {
        e = std::exp(num / den);
        out.minRadiance = std::min(out.minRadiance, e);
        out.maxRadiance = std::max(out.maxRadiance, e);
      } else if (bracket[shortest].image.pixels[3 * p + c] >= 128) {
        e = std::exp(g[254] - logDt[shortest]);  // at least this bright
        bright = true;
      } else {
        e = std::exp(g[1] - logDt[longest]);  // at most this bright
        dark = true;
      }
      out.radiance.pixels[3 * p + c] = float(e);
    }
    out.clippedBright += bright ? 1 : 0;
    out.clippedDark += dark ? 1 : 0;
  }
  if (!(out.maxRadiance > 0)) out.minRadiance = 0;
  return out;
}

}  // namespace penumbra::lighting
