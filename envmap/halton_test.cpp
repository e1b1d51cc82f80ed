// The Halton sequence of live lighting (Havran 2005 §3.2): radical inverses by hand.
#include "envmap/halton.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace penumbra::envmap {
namespace {

TEST(Halton, RadicalInversesMirrorTheDigits) {
  // Base 2: 1 = 1b -> 0.1b, 6 = 110b -> 0.011b = 3/8, exact in binary64.
  EXPECT_EQ(radicalInverse(1, 2), 0.5);
  EXPECT_EQ(radicalInverse(2, 2), 0.25);
  EXPECT_EQ(radicalInverse(3, 2), 0.75);
  EXPECT_EQ(radicalInverse(6, 2), 0.375);
  // Base 3: 5 = 12 (base 3) -> 0.21 (base 3) = 2/3 + 1/9 = 7/9.
  EXPECT_NEAR(radicalInverse(1, 3), 1.0 / 3, 1e-15);
  EXPECT_NEAR(radicalInverse(5, 3), 7.0 / 9, 1e-15);
  EXPECT_EQ(radicalInverse(0, 3), 0.0);
  EXPECT_EQ(haltonPoint(3), glm::dvec2(0.75, radicalInverse(3, 3)));
}

TEST(Halton, BasesBelowTwoAreRefused) {
  EXPECT_THROW(radicalInverse(5, 0), std::invalid_argument);
  EXPECT_THROW(radicalInverse(5, 1), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::envmap
