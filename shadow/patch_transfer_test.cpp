// The unshadowed patch transfer: reflectance x emission x the point-to-patch form factor,
// zero for a point behind the patch or facing away, and the Patch overload equal to the
// field-wise one.
#include "shadow/patch_transfer.h"

#include <gtest/gtest.h>

#include <numbers>

namespace penumbra::shadow {
namespace {

TEST(PatchTransfer, IsReflectanceTimesEmissionTimesFormFactor) {
  // A 0.01 m^2 patch 1 m above the point, facing it: F = A / (pi r^2 + A).
  const glm::dvec3 x(0.0), up(0, 1, 0), centre(0, 1, 0), down(0, -1, 0);
  const double area = 0.01, f = area / (std::numbers::pi + area);
  const glm::dvec3 rho(0.5, 0.25, 1.0), emission(10.0, 20.0, 40.0);
  const glm::dvec3 t = unshadowedTransfer(x, up, rho, emission, centre, down, area);
  EXPECT_DOUBLE_EQ(t.x, 5.0 * f);
  EXPECT_DOUBLE_EQ(t.y, 5.0 * f);
  EXPECT_DOUBLE_EQ(t.z, 40.0 * f);
  EXPECT_EQ(unshadowedTransfer(x, down, rho, emission, centre, down, area), glm::dvec3(0.0))
      << "the point faces away";
  EXPECT_EQ(unshadowedTransfer(x, up, rho, emission, centre, up, area), glm::dvec3(0.0))
      << "the patch faces away";

  scene::Patch p;
  p.centre = centre;
  p.normal = down;
  p.area = area;
  p.emission = emission;
  EXPECT_EQ(unshadowedTransfer(x, up, rho, p), t);
}

}  // namespace
}  // namespace penumbra::shadow
