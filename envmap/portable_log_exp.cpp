#include "envmap/portable_log_exp.h"

#include <cmath>
#include <limits>

namespace penumbra::envmap {

namespace {
// ln 2 split so that k · kLn2Hi is exact for |k| < 2^11 (its low 11 bits are zero).
constexpr double kLn2Hi = 0x1.62e42fefa3800p-1;
constexpr double kLn2Lo = 0x1.ef35793c76730p-45;
constexpr double kSqrtHalf = 0.70710678118654752440;
}  // namespace

double portableLog(double x) {
  if (std::isnan(x) || x < 0) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0) return -std::numeric_limits<double>::infinity();
  if (std::isinf(x)) return x;
  int e = 0;
  double m = std::frexp(x, &e);  // x = m · 2^e, m in [0.5, 1)
  if (m < kSqrtHalf) {
    m *= 2;
    --e;
  }
  // ln m = 2 atanh z, z = (m − 1)/(m + 1), |z| ≤ 0.1716: the series to z^23 leaves < 1e-19.
  const double z = (m - 1) / (m + 1);
  const double z2 = z * z;
  double p = 1.0 / 23;
  for (int k = 21; k >= 1; k -= 2) p = 1.0 / k + z2 * p;
  return (e * kLn2Lo + 2 * z * p) + e * kLn2Hi;
}

double portableExp(double x) {
  if (std::isnan(x)) return x;
  if (x > 709.78) return std::numeric_limits<double>::infinity();
  if (x < -745.2) return 0.0;
  // x = k ln 2 + r, |r| ≤ ln 2 / 2; e^r by its Taylor series to r^20/20! (< 1e-22 left).
  const double k = std::floor(x * 1.4426950408889634 + 0.5);
  const double r = (x - k * kLn2Hi) - k * kLn2Lo;
  double p = 1.0;
  for (int n = 20; n >= 1; --n) p = 1.0 + r * p / n;
  return std::ldexp(p, int(k));
}

}  // namespace penumbra::envmap
