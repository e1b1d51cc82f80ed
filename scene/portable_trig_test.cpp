#include "scene/portable_trig.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace penumbra::scene {
namespace {

TEST(PortableTrig, ExactAtRightAnglesAndCloseToLibmElsewhere) {
  double s, c;
  for (int k = -8; k <= 8; ++k) {
    sinCosDegrees(90.0 * k, s, c);
    const int q = ((k % 4) + 4) % 4;
    EXPECT_EQ(s, (q == 1) ? 1.0 : (q == 3 ? -1.0 : 0.0)) << k;
    EXPECT_EQ(c, (q == 0) ? 1.0 : (q == 2 ? -1.0 : 0.0)) << k;
  }
  for (double d = -1000.0; d < 1000.0; d += 0.37) {
    sinCosDegrees(d, s, c);
    const double r = d * std::numbers::pi / 180.0;
    EXPECT_NEAR(s, std::sin(r), 4e-15) << d;
    EXPECT_NEAR(c, std::cos(r), 4e-15) << d;
  }
  sinCosDegrees(std::nan(""), s, c);
  EXPECT_TRUE(std::isnan(s) && std::isnan(c));
}

}  // namespace
}  // namespace penumbra::scene
