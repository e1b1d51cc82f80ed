#include "raster/receiver_bands.h"

#include <algorithm>
#include <cmath>

namespace penumbra::raster {

void appendReceiverBands(int32_t minY, int32_t maxY, const std::pair<int32_t, int32_t>* runs,
                         const float* depth, const uint32_t* id, size_t stride, uint32_t owner,
                         std::vector<ReceiverBand>& out) {
  for (int32_t y0 = minY; y0 < maxY; y0 += kReceiverBandRows) {
    ReceiverBand band;
    band.x0 = band.y0 = INT32_MAX;
    band.x1 = band.y1 = INT32_MIN;
    for (int32_t y = y0; y < std::min(maxY, y0 + kReceiverBandRows); ++y) {
      const size_t row = stride * static_cast<size_t>(y);
      for (int32_t x = runs[y - minY].first; x < runs[y - minY].second; ++x) {
        if (id[row + size_t(x)] != owner) continue;
        const float z = depth[row + size_t(x)];
        if (band.matched++ == 0) band.zMin = band.zMax = z;
        band.zMin = std::min(band.zMin, z);
        band.zMax = std::max(band.zMax, z);
        band.x0 = std::min(band.x0, x);
        band.x1 = std::max(band.x1, x);
        band.y0 = std::min(band.y0, y);
        band.y1 = std::max(band.y1, y);
      }
    }
    out.push_back(band);
  }
}

namespace {

// Entries and depths up to 2^60 keep every product of q_r below 2^120 and its sum of four
// below 2^122: the binary32 q_r of a band pixel is then finite (and never NaN).
constexpr float kLimit = 0x1p60f;

// q_r of spec §7, evaluated exactly as the kernels do (binary32, this order, no FMA).
float lightRow(const float* p, float sx, float sy, float z) {
  return ((p[0] * sx + p[1] * sy) + p[2] * z) + p[3];
}

// Rounding to nearest is monotone (a <= b implies fl(a) <= fl(b)), so fl(c * x) is monotone
// in x (non-decreasing for c >= 0, non-increasing for c < 0) and fl(a + b) in each of a and b;
// q_r, in which each of sx, sy, z appears once, is therefore monotone in each of them
// separately, and over a box it lies between its values at the two corners the signs of
// its coefficients pick.
void lightRowRange(const float* p, float sx0, float sx1, float sy0, float sy1, float z0, float z1,
                   float& lo, float& hi) {
  lo = lightRow(p, p[0] >= 0 ? sx0 : sx1, p[1] >= 0 ? sy0 : sy1, p[2] >= 0 ? z0 : z1);
  hi = lightRow(p, p[0] >= 0 ? sx1 : sx0, p[1] >= 0 ? sy1 : sy0, p[2] >= 0 ? z1 : z0);
}

// floor(v) for v in [-2^31, 2^31): the conversion truncates towards zero, one less for a
// negative non-integer (exact; std::floor is a libm call without SSE4.1).
int32_t floorToInt(float v) {
  const int32_t t = static_cast<int32_t>(v);
  return static_cast<float>(t) > v ? t - 1 : t;
}

// The lanes' footprint starts along one axis, for quotients q / q3 with q in [lo, hi] and
// q3 in [lo3, hi3], lo3 > 0: fl(q / q3) is non-decreasing in q, and in q3 non-increasing
// for q >= 0 and non-decreasing for q < 0, so it lies in [lo / (lo >= 0 ? hi3 : lo3),
// hi / (hi >= 0 ? lo3 : hi3)] (possibly infinite). The kernels' start is floor(u - 0.5) for
// 2x2 PCF lanes with -1 < u - 0.5 < size, trunc(u) = floor(u) for binary lanes with
// 0 <= u < size; both monotone. Clamping to [-2, size + 1] first changes no valid lane's
// value and keeps infinities out of the conversion. False when no lane can be valid.
bool footprintRange(float lo, float hi, float lo3, float hi3, const ShadowLookup& lookup,
                    float margin, int32_t& first, int32_t& last) {
  float least = lo / (lo >= 0 ? hi3 : lo3) - margin;
  float most = hi / (hi >= 0 ? lo3 : hi3) + margin;
  if (lookup.pcf2x2) {
    least = least - 0.5f;
    most = most - 0.5f;
  }
  const float top = static_cast<float>(lookup.size) + 1.0f;
  first = floorToInt(std::clamp(least, -2.0f, top));
  last = floorToInt(std::clamp(most, -2.0f, top));
  first = std::max(first, lookup.pcf2x2 ? -1 : 0);
  last = std::min(last, lookup.size - 1);
  return first <= last;
}

}  // namespace

ReceiverBand unite(const ReceiverBand& a, const ReceiverBand& b) {
  if (a.matched == 0) return b;
  if (b.matched == 0) return a;
  return {std::min(a.x0, b.x0), std::min(a.y0, b.y0),     std::max(a.x1, b.x1),
          std::max(a.y1, b.y1), std::min(a.zMin, b.zMin), std::max(a.zMax, b.zMax),
          a.matched + b.matched};
}

LightFootprint::LightFootprint(const ShadowLookup& lookup, const ShadowMap& map)
    : lookup_(lookup), map_(map), bounded_(true) {
  for (float entry : lookup.p) bounded_ = bounded_ && std::fabs(entry) <= kLimit;
}

bool LightFootprint::unwritten(const ReceiverBand& band) const {
  if (!bounded_ || !(std::fabs(band.zMin) <= kLimit && std::fabs(band.zMax) <= kLimit)) {
    return false;
  }
  const float* p = lookup_.p;
  // Pixel centres (spec §7), exact in binary32.
  const float sx0 = static_cast<float>(band.x0) + 0.5f, sx1 = static_cast<float>(band.x1) + 0.5f;
  const float sy0 = static_cast<float>(band.y0) + 0.5f, sy1 = static_cast<float>(band.y1) + 0.5f;
  float lo0, hi0, lo1, hi1, lo3, hi3;
  lightRowRange(p + 12, sx0, sx1, sy0, sy1, band.zMin, band.zMax, lo3, hi3);
  // Every pixel must pass the kernels' q3 > 0; a pixel that fails it gets W = 0 anyway, but
  // the quotient bounds need a positive divisor.
  if (!(lo3 > 0)) return false;
  lightRowRange(p, sx0, sx1, sy0, sy1, band.zMin, band.zMax, lo0, hi0);
  lightRowRange(p + 4, sx0, sx1, sy0, sy1, band.zMin, band.zMax, lo1, hi1);
  float margin = 0;
  if (lookup_.penumbraScale > 0) {
    // The kernels' d = fl(q2 / q3) is at most fl(hi2 / lo3) (hi2 >= 0) or fl(hi2 / hi3), and
    // fl(K fl(d - nearest)) is non-decreasing in d: no pixel's r exceeds this one (NaN: the
    // cap). W reads texels within its box w <= r or the 2x2 PCF's footprint only; the search
    // decides which, and W = 0 wherever neither meets a written texel.
    float lo2, hi2;
    lightRowRange(p + 8, sx0, sx1, sy0, sy1, band.zMin, band.zMax, lo2, hi2);
    const float reach = lookup_.penumbraScale * (hi2 / (hi2 >= 0 ? lo3 : hi3) - lookup_.nearest);
    const float r =
        reach > 1.0f ? (reach < kMaxPenumbraHalfWidth ? reach : kMaxPenumbraHalfWidth) : 1.0f;
    margin = r + 1.0f;
  }
  int32_t i0, i1, j0, j1;
  if (!footprintRange(lo0, hi0, lo3, hi3, lookup_, margin, i0, i1)) return true;
  if (!footprintRange(lo1, hi1, lo3, hi3, lookup_, margin, j0, j1)) return true;
  return !map_.blocksWritten(i0, j0, i1, j1);
}

}  // namespace penumbra::raster
