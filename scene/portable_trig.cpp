#include "scene/portable_trig.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace penumbra::scene {

void sinCosDegrees(double degrees, double& s, double& c) {
  if (!std::isfinite(degrees)) {
    s = c = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  // Reduce to r in [-45, 45] degrees and a quadrant, exactly: fmod and the subtraction of a
  // multiple of 90 from a value below 360 in magnitude lose no bits.
  double d = std::fmod(degrees, 360.0);
  if (d < 0) d += 360.0;
  const int quadrant = static_cast<int>(std::floor((d + 45.0) / 90.0)) % 4;
  const double r = (d - 90.0 * std::floor((d + 45.0) / 90.0)) * (std::numbers::pi / 180.0);
  // Taylor series to x^15 / x^16: for |x| <= pi/4 the first omitted term is below 2e-19.
  const double x2 = r * r;
  double ps = -1.0 / 1307674368000.0;  // -1/15!
  ps = 1.0 / 6227020800.0 + x2 * ps;   // 1/13!
  ps = -1.0 / 39916800.0 + x2 * ps;
  ps = 1.0 / 362880.0 + x2 * ps;
  ps = -1.0 / 5040.0 + x2 * ps;
  ps = 1.0 / 120.0 + x2 * ps;
  ps = -1.0 / 6.0 + x2 * ps;
  const double sr = r + r * x2 * ps;
  double pc = 1.0 / 20922789888000.0;  // 1/16!
  pc = -1.0 / 87178291200.0 + x2 * pc;
  pc = 1.0 / 479001600.0 + x2 * pc;
  pc = -1.0 / 3628800.0 + x2 * pc;
  pc = 1.0 / 40320.0 + x2 * pc;
  pc = -1.0 / 720.0 + x2 * pc;
  pc = 1.0 / 24.0 + x2 * pc;
  pc = -0.5 + x2 * pc;
  const double cr = 1.0 + x2 * pc;
  switch (quadrant) {
    case 0:
      s = sr;
      c = cr;
      break;
    case 1:
      s = cr;
      c = -sr;
      break;
    case 2:
      s = -sr;
      c = -cr;
      break;
    default:
      s = -cr;
      c = sr;
      break;
  }
}

}  // namespace penumbra::scene
