#include "envmap/envmap_sampling.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "core/colour.h"

namespace penumbra::envmap {

glm::dvec3 totalPower(const LightSet& lights) {
  glm::dvec3 sum(0.0);
  for (const DirectionalLight& light : lights) sum += light.power;
  return sum;
}

namespace {

// Running sums to a CDF in place: cdf[0] = 0, cdf[k] = Σ_{<k} mass, normalised to end at
// exactly 1; a massless row becomes the uniform CDF.
void normaliseCdf(double* cdf, size_t bins) {
  const double total = cdf[bins];
  for (size_t k = 1; k < bins; ++k) cdf[k] = total > 0 ? cdf[k] / total : double(k) / double(bins);
  cdf[bins] = 1.0;
}

// The conditional CDFs are built by sumRow, which divides the row before's running sums by
// their total while it adds up its own (below), cdf[bins] included: total / total, 1 for a row
// with mass, NaN (0 / 0) for one without, which finishCdf then makes the uniform CDF as
// normaliseCdf does. `divide`: the divisions were not done yet (the last row).
void finishCdf(double* cdf, size_t bins, bool divide = false) {
  if (divide || !(cdf[bins] > 0))
    normaliseCdf(cdf, bins);
  else
    cdf[bins] = 1.0;
}

struct RowSums {
  double r = 0, g = 0, b = 0;  // radiance, over all rows so far, in pixel order
  float lowest = 0;            // the least sample of the last row (or 0)
};

using Double2 = double __attribute__((vector_size(16)));

// One map row: its pixels copied from `in` to `copy`, their luminance's running sums into
// cdf[0 … cols] and their radiance added to `sums`; with kDividePrevious, also previous[k] /=
// previous[cols] for k = 1 … cols − 1 (the row before's normalisation, which normaliseCdf
// would do after it: the same divisions, so the same bits, but here, two at a time, the divider
// works in the shadow of this row's chain of additions instead of after it).
//
// Checks, without a branch per sample: a NaN or infinite sample makes the row's running sum
// NaN or infinite (a double sum of finite floats cannot overflow); a negative one makes
// `lowest` negative (−0 is not: the per-sample test of throwBadPixel accepts it too).
template <bool kDividePrevious>
void sumRow(const float* in, float* copy, double* cdf, uint32_t cols, double* previous,
            RowSums& sums) {
  const double total = kDividePrevious ? previous[cols] : 1.0;
  const Double2 divisor = {total, total};
  double running = 0.0, r = sums.r, g = sums.g, b = sums.b;
  float lowest = 0.0f;
  cdf[0] = 0.0;
  // Per pixel: r, g, b converted and summed in pixel order, the luminance (core::luminance's
  // operations) added to the running sum.
  const auto pixel = [&](uint32_t col) {
    const float* p = in + size_t(col) * 3;
    float* o = copy + size_t(col) * 3;
    o[0] = p[0], o[1] = p[1], o[2] = p[2];
    lowest = std::min(lowest, std::min(p[0], std::min(p[1], p[2])));
    const glm::dvec3 rgb(p[0], p[1], p[2]);
    r += rgb.x, g += rgb.y, b += rgb.z;
    // Havran 2005 §3.1: equal solid angle per pixel, so the PDF is the luminance itself.
    running += core::luminance(rgb);
    cdf[col + 1] = running;
  };
  uint32_t col = 0;
  for (; col + 2 <= cols; col += 2) {
    pixel(col);
    pixel(col + 1);
    if constexpr (kDividePrevious) {
      // previous[col + 1], previous[col + 2]: up to previous[cols] (total / total, set to
      // exactly 1 by finishCdf anyway).
      Double2 v;
      std::memcpy(&v, previous + col + 1, sizeof v);
      v = v / divisor;
      std::memcpy(previous + col + 1, &v, sizeof v);
    }
  }
  for (; col < cols; ++col) {
    pixel(col);
    if constexpr (kDividePrevious) previous[col + 1] = previous[col + 1] / total;
  }
  sums.r = r, sums.g = g, sums.b = b;
  sums.lowest = lowest;
}

// The first sample of `row` that is not a finite non-negative number, named in the error.
[[noreturn]] void throwBadPixel(const HemisphereMap& map, uint32_t row, const std::string& label) {
  for (uint32_t col = 0; col < map.cols(); ++col) {
    const float* p = map.radiance.pixel(col, row);
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(p[c]) || p[c] < 0.0f)
        throw EnvmapError(
            label, "pixel (" + std::to_string(col) + ", " + std::to_string(row) + ")",
            "radiance " + std::to_string(p[c]) + " is not a finite non-negative number");
  }
  throw EnvmapError(label, "row " + std::to_string(row), "a radiance is not finite non-negative");
}

// The position of `x` in bin `k` of a CDF, in [0, 1]; 0 for a bin of no mass (which a search
// for the largest k with cdf[k] ≤ x only returns at the ends).
double positionInBin(double x, double lo, double hi) {
  if (!(hi > lo)) return 0.0;
  return std::clamp((x - lo) / (hi - lo), 0.0, 1.0);
}

}  // namespace

EnvmapDistribution::EnvmapDistribution(const HemisphereMap& map, const std::string& label) {
  update(map, label);
}

void EnvmapDistribution::update(const HemisphereMap& map, const std::string& label) {
  rows_ = cols_ = 0;  // empty until the map has passed every check
  if (map.rows() == 0 || map.cols() == 0)
    throw EnvmapError(label, "",
                      "empty map (" + std::to_string(map.cols()) + " × " +
                          std::to_string(map.rows()) + " pixels)");
  if (!map.radiance.hasExpectedSize())
    throw EnvmapError(label, "",
                      "holds " + std::to_string(map.radiance.pixels.size()) +
                          " samples, expected " + std::to_string(map.radiance.pixelCount() * 3));
  const uint32_t rows = map.rows(), cols = map.cols();
  const float* in = map.radiance.pixels.data();
  radiance_.resize(map.radiance.pixels.size());
  marginal_.assign(rows + 1, 0.0);
  conditional_.resize(size_t(rows) * (cols + 1));
  const double solidAngle = map.pixelSolidAngle();
  RowSums sums;
  for (uint32_t row = 0; row < rows; ++row) {
    double* cdf = &conditional_[size_t(row) * (cols + 1)];
    const size_t first = size_t(row) * cols * 3;
    if (row == 0)
      sumRow<false>(in + first, &radiance_[first], cdf, cols, nullptr, sums);
    else
      sumRow<true>(in + first, &radiance_[first], cdf, cols, cdf - (cols + 1), sums);
    if (!(sums.lowest >= 0.0f) || !std::isfinite(cdf[cols])) throwBadPixel(map, row, label);
    marginal_[row + 1] = marginal_[row] + cdf[cols];
    if (row > 0) finishCdf(cdf - (cols + 1), cols);
  }
  finishCdf(&conditional_[size_t(rows - 1) * (cols + 1)], cols, true);
  const glm::dvec3 radianceSum(sums.r, sums.g, sums.b);
  totalLuminance_ = marginal_[rows] * solidAngle;
  totalPower_ = radianceSum * solidAngle;
  normaliseCdf(marginal_.data(), rows);
  rows_ = rows;
  cols_ = cols;
}

void EnvmapDistribution::requireMap() const {
  if (rows_ == 0) throw EnvmapError("light sampling", "", "no map (its last update failed)");
}

double EnvmapDistribution::conditionalCdf(uint32_t row0, uint32_t row1, double t,
                                          uint32_t j) const {
  const double a = conditional_[size_t(row0) * (cols_ + 1) + j];
  const double b = conditional_[size_t(row1) * (cols_ + 1) + j];
  return (1.0 - t) * a + t * b;
}

DiskPolar EnvmapDistribution::warp(const DiskPolar& p) const {
  requireMap();
  // Marginal over u: the largest row whose CDF value is ≤ u, then linear inside it.
  uint32_t row =
      uint32_t(std::upper_bound(marginal_.begin(), marginal_.end(), p.u) - marginal_.begin());
  row = std::clamp<uint32_t>(row, 1, rows_) - 1;
  while (row > 0 && !(marginal_[row + 1] > marginal_[row])) --row;  // u = 1 past empty rows
  const double u = (row + positionInBin(p.u, marginal_[row], marginal_[row + 1])) / double(rows_);

  // Conditional over the azimuth, interpolated between the CDFs of the two rows whose centres
  // enclose u (Havran 2005 §3.1): continuous in u across row boundaries.
  const double x = u * rows_ - 0.5;
  uint32_t row0 = 0, row1 = 0;
  double t = 0;
  if (x >= double(rows_ - 1)) {
    row0 = row1 = rows_ - 1;
  } else if (x > 0.0) {
    row0 = uint32_t(x);
    row1 = row0 + 1;
    t = x - row0;
  }
  uint32_t lo = 0, hi = cols_;  // F(lo) ≤ v; F(hi) > v or hi = cols
  while (hi - lo > 1) {
    const uint32_t mid = lo + (hi - lo) / 2;
    if (conditionalCdf(row0, row1, t, mid) <= p.turns)
      lo = mid;
    else
      hi = mid;
  }
  const double turns = (lo + positionInBin(p.turns, conditionalCdf(row0, row1, t, lo),
                                           conditionalCdf(row0, row1, t, lo + 1))) /
                       double(cols_);
  return {u, turns < 1.0 ? turns : 0.0};
}

LightSet EnvmapDistribution::sample(const SamplePattern& pattern, uint32_t count) const {
  if (count > pattern.size())
    throw EnvmapError(
        "light sampling", "count",
        std::to_string(count) + " lights asked of a pattern of " + std::to_string(pattern.size()));
  requireMap();
  LightSet lights(count);
  if (count == 0) return lights;
  const double share = totalLuminance_ / count;
  glm::dvec3 sum(0.0);
  for (uint32_t i = 0; i < count; ++i) {
    const glm::dvec2& s = pattern.point(i + 1);
    const DiskPolar w = warp(concentricSquareToDisk(s.x, s.y));
    DirectionalLight& light = lights[i];
    light.id = i + 1;
    light.direction = diskToHemisphere(w);
    // The colour of the pixel the light lands in, at the light's luminance share.
    const uint32_t row = std::min(rows_ - 1, uint32_t(w.u * rows_));
    const uint32_t col = std::min(cols_ - 1, uint32_t(w.turns * cols_));
    const float* p = &radiance_[(size_t(row) * cols_ + col) * 3];
    const glm::dvec3 rgb(p[0], p[1], p[2]);
    const double y = core::luminance(rgb);
    light.power = y > 0 ? rgb * (share / y) : glm::dvec3(share);
    sum += light.power;
  }
  // Per-channel scale: the lights' RGB powers add up to the map's (energy preservation).
  for (int c = 0; c < 3; ++c) {
    const double scale = sum[c] > 0 ? totalPower_[c] / sum[c] : 0.0;
    for (DirectionalLight& light : lights)
      light.power[c] = sum[c] > 0 ? light.power[c] * scale : totalPower_[c] / count;
  }
  return lights;
}

}  // namespace penumbra::envmap
