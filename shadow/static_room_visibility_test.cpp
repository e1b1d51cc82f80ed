// The room's own occlusion of live lighting's distant lights (static_room_visibility.h) on
// the bundled showroom, whose only furniture is a desk over [4.4, 5.8] x [0, 0.75] x
// [3.4, 4.2]: the shell (floor, walls, ceiling and its lamps) never occludes, the desk does,
// exactly where a ray cast against the desk's box says; a light's visibility moves
// continuously with its direction.
#include "shadow/static_room_visibility.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "shadow/scene_bundle.h"
#include "tests/showroom_bundle.h"

namespace penumbra::shadow {
namespace {

const glm::dvec3 kDeskLo(4.4, 0, 3.4), kDeskHi(5.8, 0.75, 4.2);

// The ray's entry and exit of the desk's box grown by `grow` on every side (slab test);
// empty when it misses.
bool hitsDesk(const glm::dvec3& o, const glm::dvec3& d, double& near, double& far,
              double grow = 0) {
  near = 0;
  far = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    double t0 = (kDeskLo[a] - grow - o[a]) / d[a], t1 = (kDeskHi[a] + grow - o[a]) / d[a];
    if (t0 > t1) std::swap(t0, t1);
    near = std::max(near, t0);
    far = std::min(far, t1);
  }
  return near <= far;
}

struct Showroom {
  const SceneBundle& b = penumbra::testing::showroomBundle();
  scene::PatchMesh mesh = patchMeshOf(b);
  StaticRoomVisibility visibility{mesh, b.transfers.receiverVertices, nullptr};

  // The receiver vertex nearest `p`.
  uint32_t nearest(const glm::dvec3& p) const {
    uint32_t best = 0;
    double bestDistance = std::numeric_limits<double>::infinity();
    for (uint32_t r = 0; r < b.transfers.receiverVertices.size(); ++r) {
      const double d = glm::length(mesh.positions[b.transfers.receiverVertices[r]] - p);
      if (d < bestDistance) {
        bestDistance = d;
        best = r;
      }
    }
    return best;
  }
};

TEST(StaticRoomVisibility, TheDeskOccludesTheShellDoesNot) {
  const Showroom s;
  ASSERT_GT(s.visibility.occluderTriangles(), 0u);
  EXPECT_GT(s.visibility.partlyBlockedVertices(), 0u);

  // Above the desk's top every ray of the upper hemisphere misses the desk, and the rest of
  // the room is shell: those receivers see everything.
  size_t above = 0;
  for (uint32_t r = 0; r < s.b.transfers.receiverVertices.size(); ++r) {
    if (s.mesh.positions[s.b.transfers.receiverVertices[r]].y < kDeskHi.y + 0.01) continue;
    ++above;
    EXPECT_TRUE(s.visibility.seesEverything(r)) << "receiver vertex " << r;
  }
  EXPECT_GT(above, 20u);
  // Mid-floor: the desk, 3.5 m away, hides only a few low directions (the lowest ring of
  // cells is 3.6 degrees up; the desk's top is 10 degrees up seen from there).
  const uint32_t far = s.nearest({1.5, 0, 1.5});
  size_t hidden = 0;
  for (uint32_t c = 0; c < StaticRoomVisibility::kGrid * StaticRoomVisibility::kGrid; ++c) {
    hidden += !s.visibility.sees(far, c);
  }
  EXPECT_GT(hidden, 0u);
  EXPECT_LT(hidden, 20u);

  const uint32_t beside = s.nearest({5.1, 0, 3.1});  // the floor in front of the desk
  ASSERT_FALSE(s.visibility.seesEverything(beside));
  const auto seen = [&](glm::dvec3 d) {
    return s.visibility.visibility(beside, StaticRoomVisibility::lookup(glm::normalize(d)));
  };
  EXPECT_EQ(seen({0, 0.25, 1}), 0.0) << "low, over the desk: hidden";
  EXPECT_EQ(seen({0, 1, 0}), 1.0) << "overhead";
  EXPECT_EQ(seen({0, 0.25, -1}), 1.0) << "low, away from the desk";
}

// Every cell of every floor vertex away from the desk's footprint, against the desk's box:
// the same answer, except for rays that only graze an edge (within 1 mm).
TEST(StaticRoomVisibility, AgreesWithARayCastAgainstTheDesksBox) {
  const Showroom s;
  size_t compared = 0, hidden = 0;
  for (uint32_t r = 0; r < s.b.transfers.receiverVertices.size(); ++r) {
    const uint32_t v = s.b.transfers.receiverVertices[r];
    const glm::dvec3 p = s.mesh.positions[v];
    if (std::abs(p.y) > 1e-9 || s.mesh.normals[v].y < 0.99) continue;  // the floor only
    if (p.x > kDeskLo.x - 0.01 && p.x < kDeskHi.x + 0.01 && p.z > kDeskLo.z - 0.01 &&
        p.z < kDeskHi.z + 0.01) {
      continue;  // under or against the desk
    }
    const glm::dvec3 origin = p + glm::dvec3(0, 1e-3, 0);
    for (int j = 0; j < StaticRoomVisibility::kGrid; ++j) {
      for (int i = 0; i < StaticRoomVisibility::kGrid; ++i) {
        const glm::dvec3 d = StaticRoomVisibility::cellDirection(i, j);
        double near = 0, far = 0;
        const bool hit = hitsDesk(origin, d, near, far);
        // Grazing: through a sliver of the box, or past it by less than 1 mm (the bundle's
        // float corners differ from these by 2e-7 m, and the refined floor's dyadic vertices
        // can line up with a cell's dyadic direction exactly on the desk's edge).
        if (hit && far - near < 1e-3) continue;
        if (!hit && hitsDesk(origin, d, near, far, 1e-3)) continue;
        const bool sees = s.visibility.sees(r, uint32_t(j * StaticRoomVisibility::kGrid + i));
        ASSERT_EQ(sees, !hit) << "vertex at " << p.x << ", " << p.z << ", cell " << i << ", " << j;
        ++compared;
        hidden += hit;
      }
    }
  }
  EXPECT_GT(compared, 10000u);
  EXPECT_GT(hidden, 100u);
}

TEST(StaticRoomVisibility, LookupIsBilinearAndContinuous) {
  for (int j = 0; j < StaticRoomVisibility::kGrid; j += 5) {
    for (int i = 0; i < StaticRoomVisibility::kGrid; i += 3) {
      const auto l = StaticRoomVisibility::lookup(StaticRoomVisibility::cellDirection(i, j));
      double sum = 0, onCell = 0;
      for (size_t k = 0; k < 4; ++k) {
        EXPECT_GE(l.weight[k], 0.0);
        sum += l.weight[k];
        if (l.cell[k] == j * StaticRoomVisibility::kGrid + i) onCell += l.weight[k];
      }
      EXPECT_NEAR(sum, 1.0, 1e-12);
      EXPECT_NEAR(onCell, 1.0, 1e-9) << "a cell's own centre: " << i << ", " << j;
    }
  }
  // A light sweeping low over the desk, seen from the floor in front of it: visibility falls
  // from 1 to 0 in steps no larger than the sweep's step allows (no pop).
  const Showroom s;
  const uint32_t beside = s.nearest({5.1, 0, 3.1});
  double last = s.visibility.visibility(beside, StaticRoomVisibility::lookup({0, 1, 0}));
  EXPECT_EQ(last, 1.0);
  double largestStep = 0;
  for (int step = 1; step <= 400; ++step) {
    const double elevation = (90.0 - 80.0 * step / 400) * 3.14159265358979 / 180;
    const double now = s.visibility.visibility(
        beside, StaticRoomVisibility::lookup({0, std::sin(elevation), std::cos(elevation)}));
    largestStep = std::max(largestStep, std::abs(now - last));
    last = now;
  }
  EXPECT_EQ(last, 0.0) << "10 degrees over the desk";
  EXPECT_LT(largestStep, 0.05) << "0.2 degree steps";
}

TEST(StaticRoomVisibility, TheSameBitsOnAnyPool) {
  const Showroom s;
  core::JobPool pool(2);
  const StaticRoomVisibility pooled(s.mesh, s.b.transfers.receiverVertices, &pool);
  for (uint32_t r = 0; r < s.b.transfers.receiverVertices.size(); ++r) {
    for (uint32_t c = 0; c < StaticRoomVisibility::kGrid * StaticRoomVisibility::kGrid; ++c) {
      ASSERT_EQ(pooled.sees(r, c), s.visibility.sees(r, c)) << r << ", " << c;
    }
  }
}

}  // namespace
}  // namespace penumbra::shadow
