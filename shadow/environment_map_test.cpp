#include "shadow/environment_map.h"
#include "core/random.h"

#include <gtest/gtest.h>

#include <cstring>

#include "scene/patch_mesh.h"
#include "scene/sha256.h"

namespace penumbra::shadow {
namespace {

TEST(PhongLobe, RingsSplitTheLobeEnergy) {
  const PhongLobe diffuseLike(0.0f);  // cos^0: energy 1 - c below c
  EXPECT_NEAR(diffuseLike.cosTheta[0], 0.875, 1e-6);
  EXPECT_NEAR(diffuseLike.cosTheta[3], 0.125, 1e-6);
  const PhongLobe sharp(1000.0f);
  for (int k = 0; k < kLobeRings; ++k) {
    EXPECT_GT(sharp.cosTheta[size_t(k)], 0.995f);
    const double c = sharp.cosTheta[size_t(k)];
    EXPECT_NEAR(std::pow(c, 1001.0), 1.0 - (k + 0.5) / kLobeRings, 1e-4);
  }
}

// A 4 x 3 x 5 room whose six walls shine in six different colours, seen from inside.
struct ColouredRoom {
  scene::PatchMesh mesh;
  std::vector<glm::vec3> radiance;
  glm::vec3 wallColour(const glm::dvec3& normal) const {
    // Walls face into the room: the wall seen along +x has normal -x.
    const glm::dvec3 seen = -normal;
    if (seen.x > 0.5) return {0.8f, 0.1f, 0.1f};
    if (seen.x < -0.5) return {0.1f, 0.8f, 0.1f};
    if (seen.y > 0.5) return {0.1f, 0.1f, 0.8f};
    if (seen.y < -0.5) return {0.8f, 0.8f, 0.1f};
    if (seen.z > 0.5) return {0.1f, 0.8f, 0.8f};
    return {0.8f, 0.1f, 0.8f};
  }
  ColouredRoom() {
    scene::RoomDescription room;
    const scene::Material m{glm::dvec3(0.5), glm::dvec3(0.0)};
    room.addRoomShell({glm::dvec3(0.0), glm::dvec3(4.0, 3.0, 5.0)}, m, m, m);
    mesh = scene::buildPatchMesh(room, 0.5);
    for (const scene::Patch& p : mesh.patches) radiance.push_back(wallColour(p.normal));
  }
};

// The coloured room shaded for the environment map through a gamma-2.2 tone curve of the
// given scale.
struct ShadedRoom {
  explicit ShadedRoom(double toneScale)
      : tone(ToneCurve::gamma(toneScale, 2.2)),
        inverse(tone),
        shaded(roomForEnvironment(room.mesh.toRasterMesh(), room.mesh.trianglePatch, room.radiance,
                                  tone)) {}
  ColouredRoom room;
  ToneCurve tone;
  ToneInverse inverse;
  raster::ShadedMesh shaded;
};

TEST(EnvironmentMap, EachDirectionSeesItsWall) {
  const auto& [room, tone, inverse, shaded] = ShadedRoom(1.0);
  CubeEnvironmentMap map;
  renderEnvironmentMap(shaded, glm::vec3(1.5f, 1.2f, 2.0f), 32, 20.0f, map);
  ASSERT_EQ(map.rgba.size(), size_t{6} * 32 * 32 * 4);
  const glm::vec3 dirs[] = {
      {1, 0, 0},           {-1, 0, 0}, {0, 1, 0},          {0, -1, 0},
      {0, 0, 1},           {0, 0, -1}, {0.9f, 0.3f, 0.2f}, {-0.2f, 0.4f, -0.9f},
      {0.1f, -0.95f, 0.3f}};
  for (const glm::vec3& d : dirs) {
    const glm::vec3 want = room.wallColour(-glm::dvec3(
        std::abs(d.x) >= std::max(std::abs(d.y), std::abs(d.z)) ? glm::sign(d.x) : 0,
        std::abs(d.y) > std::abs(d.x) && std::abs(d.y) >= std::abs(d.z) ? glm::sign(d.y) : 0,
        std::abs(d.z) > std::max(std::abs(d.x), std::abs(d.y)) ? glm::sign(d.z) : 0));
    const glm::vec3 got = map.lookup(glm::normalize(d), inverse);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 0.03) << d.x << d.y << d.z;
  }
  // Zero and NaN directions are safe.
  EXPECT_EQ(map.lookup(glm::vec3(0.0f), inverse), glm::vec3(0.0f));
  EXPECT_EQ(map.lookup(glm::vec3(std::nanf("")), inverse), glm::vec3(0.0f));
  // Rendering is deterministic.
  CubeEnvironmentMap again;
  renderEnvironmentMap(shaded, glm::vec3(1.5f, 1.2f, 2.0f), 32, 20.0f, again);
  EXPECT_EQ(map.rgba, again.rgba);
}

TEST(EnvironmentMap, SharpLobeMirrorsTheEye) {
  const auto& [room, tone, inverse, shaded] = ShadedRoom(1.0);
  CubeEnvironmentMap map;
  renderEnvironmentMap(shaded, glm::vec3(2.0f, 1.5f, 2.5f), 32, 20.0f, map);
  const PhongLobe mirror(4000.0f), broad(1.0f);
  // Eye straight above a +y-facing point: the mirror direction is up, the ceiling's colour.
  const glm::vec3 p(2.0f, 1.0f, 2.5f), eye(2.0f, 2.5f, 2.5f);
  const glm::vec3 s = specularRadiance(map, inverse, mirror, p, glm::vec3(0, 2, 0), eye);
  EXPECT_NEAR(s.z, 0.8, 0.03);
  EXPECT_NEAR(s.x, 0.1, 0.03);
  // A broad lobe mixes in the walls: less blue, more red and green.
  const glm::vec3 b = specularRadiance(map, inverse, broad, p, glm::vec3(0, 1, 0), eye);
  EXPECT_LT(b.z, s.z - 0.1f);
  EXPECT_GT(b.x, s.x + 0.05f);
  EXPECT_EQ(specularRadiance(map, inverse, mirror, p, glm::vec3(0.0f), eye), glm::vec3(0.0f));
}

// Golden bytes of the map and of 500 lobe lookups (design §3: same on every ISA; checked
// natively and under qemu-aarch64). A change here is a deliberate, explained commit.
TEST(EnvironmentMap, GoldenBytes) {
  const auto& [room, tone, inverse, shaded] = ShadedRoom(1.3);
  CubeEnvironmentMap map;
  renderEnvironmentMap(shaded, glm::vec3(1.7f, 0.9f, 2.2f), 24, 20.0f, map);
  std::vector<uint8_t> bytes = map.rgba;
  uint64_t state = 7;
  auto next = [&] {
    state = core::splitmix64(state);
    return float(int64_t(state >> 40) - (int64_t{1} << 23)) * 0x1.0p-23f;  // exact, [-1, 1)
  };
  const PhongLobe lobe(37.0f);
  for (int i = 0; i < 500; ++i) {
    // Braced initializers: the draws happen left to right on every compiler.
    const glm::vec3 p{1.7f + 0.3f * next(), 0.9f + 0.3f * next(), 2.2f + 0.3f * next()};
    const glm::vec3 n{next(), next(), next()};
    const glm::vec3 s = specularRadiance(map, inverse, lobe, p, n, glm::vec3(0.3f, 1.6f, 0.2f));
    const size_t at = bytes.size();
    bytes.resize(at + sizeof(s));
    std::memcpy(bytes.data() + at, &s, sizeof(s));
  }
  EXPECT_EQ(scene::sha256Hex(bytes),
            "f0f4b04b53c62e55d440d7e9535ab7062e8a01c688db3ad6df0ff39e000a2cd2");
}

}  // namespace
}  // namespace penumbra::shadow
