#include "lighting/irradiance_volume_gather.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>

#include "lighting/patch_radiosity.h"

namespace penumbra::lighting {
namespace {

using glm::dvec3;

// E(n) / pi of a distant radiance function by brute-force midpoint quadrature in
// (cos theta, phi) around +z: what the SH9 reconstruction approximates.
template <class L>
double bruteIrradianceOverPi(const L& radiance, const dvec3& n, int steps) {
  double sum = 0;
  const double cell = (2.0 / steps) * (2 * std::numbers::pi / (2 * steps));
  for (int a = 0; a < steps; ++a) {
    const double z = -1 + (a + 0.5) * 2.0 / steps;
    const double r = std::sqrt(1 - z * z);
    for (int b = 0; b < 2 * steps; ++b) {
      const double phi = (b + 0.5) * 2 * std::numbers::pi / (2 * steps);
      const dvec3 d(r * std::cos(phi), r * std::sin(phi), z);
      const double c = glm::dot(n, d);
      if (c > 0) sum += radiance(d) * c * cell;
    }
  }
  return sum / std::numbers::pi;
}

double shIrradianceOverPi(const std::array<double, shadow::kShFloats>& c, const dvec3& n) {
  double basis[shadow::kShCoefficients];
  shadow::shBasis9(n.x, n.y, n.z, basis);
  double e = 0;
  for (int k = 0; k < shadow::kShCoefficients; ++k) e += basis[k] * c[size_t(k * 3)];
  return e;
}

std::vector<dvec3> testNormals() {
  std::vector<dvec3> out;
  for (int i = 0; i < 64; ++i) {
    out.push_back(stratifiedSphereDirection(4, 99, i % 32));
  }
  out.push_back(dvec3(0, 0, 1));
  out.push_back(dvec3(0, 0, -1));
  return out;
}

// Worst |SH9 - brute force| over the test normals, relative to the largest brute-force value.
template <class L>
double worstRelativeError(const L& radiance, int directionsPerSide, double* peakRatio = nullptr) {
  const auto c =
      projectIrradianceSh([&](const dvec3& d) { return dvec3(radiance(d)); }, directionsPerSide, 7);
  double worst = 0, peak = 0;
  std::vector<std::pair<double, double>> pairs;
  for (const dvec3& n : testNormals()) {
    const double exact = bruteIrradianceOverPi(radiance, n, 400);
    pairs.emplace_back(shIrradianceOverPi(c, n), exact);
    peak = std::max(peak, exact);
  }
  for (auto [sh, exact] : pairs) worst = std::max(worst, std::abs(sh - exact) / peak);
  if (peakRatio) *peakRatio = worst;
  return worst;
}

TEST(IrradianceSh, ConstantEnvironment) {
  // Only the midpoint rule in cos theta errs (O(1/n^2)): 0.4% at the builder's n = 12.
  EXPECT_LT(worstRelativeError([](const dvec3&) { return 2.5; }, 12), 5e-3);
  EXPECT_LT(worstRelativeError([](const dvec3&) { return 2.5; }, 48), 5e-4);
}

TEST(IrradianceSh, CosineLobeWithinOnePercent) {
  const dvec3 a = glm::normalize(dvec3(0.3, 0.8, 0.5));
  const double err =
      worstRelativeError([&](const dvec3& d) { return std::max(0.0, glm::dot(a, d)); }, 24);
  std::cout << "cosine lobe: worst SH9 error " << 100 * err << "% of peak irradiance\n";
  EXPECT_LT(err, 0.01);
}

TEST(IrradianceSh, SmallBrightDiscMatchesBruteForceSh9WithinOnePercent) {
  // A small bright disc (10 degree radius) over a dim sky. The gather is checked against
  // the same nine-coefficient irradiance computed by brute-force quadrature: what the
  // stratified projection must reproduce. (The truncation itself is measured below.)
  const dvec3 a = glm::normalize(dvec3(-0.2, 0.9, 0.4));
  const double cosR = std::cos(10.0 * std::numbers::pi / 180);
  auto sky = [&](const dvec3& d) { return glm::dot(a, d) > cosR ? 200.0 : 1.0; };
  const auto c = projectIrradianceSh([&](const dvec3& d) { return dvec3(sky(d)); }, 64, 7);
  // Brute force: midpoint quadrature of L Y_k over the sphere, times A_l / pi.
  std::array<double, shadow::kShFloats> ref{};
  const int steps = 600;
  const double cell = (2.0 / steps) * (2 * std::numbers::pi / (2 * steps));
  for (int i = 0; i < steps; ++i) {
    const double z = -1 + (i + 0.5) * 2.0 / steps, r = std::sqrt(1 - z * z);
    for (int j = 0; j < 2 * steps; ++j) {
      const double phi = (j + 0.5) * std::numbers::pi / steps;
      const dvec3 d(r * std::cos(phi), r * std::sin(phi), z);
      double basis[shadow::kShCoefficients];
      shadow::shBasis9(d.x, d.y, d.z, basis);
      for (int k = 0; k < shadow::kShCoefficients; ++k) {
        ref[size_t(k * 3)] += sky(d) * basis[k] * cell * shadow::kShIrradianceOverPi[size_t(k)];
      }
    }
  }
  double worst = 0, peak = 0;
  for (const dvec3& n : testNormals()) peak = std::max(peak, shIrradianceOverPi(ref, n));
  for (const dvec3& n : testNormals()) {
    worst = std::max(worst, std::abs(shIrradianceOverPi(c, n) - shIrradianceOverPi(ref, n)) / peak);
  }
  std::cout << "disc + sky: worst SH9 gather error " << 100 * worst << "% of peak\n";
  EXPECT_LT(worst, 0.01);
}

TEST(IrradianceSh, IsolatedDiscShowsTheKnownOrderTwoTruncation) {
  // A lone small source is the worst case of nine coefficients (Ramamoorthi & Hanrahan
  // 2001 §3: the clamped cosine's l = 4 band is dropped): about 6% of the peak towards the
  // disc. Measured here so the limit is stated, not hidden.
  const dvec3 a = glm::normalize(dvec3(0.1, 0.2, 0.97));
  const double cosR = std::cos(10.0 * std::numbers::pi / 180);
  const double err =
      worstRelativeError([&](const dvec3& d) { return glm::dot(a, d) > cosR ? 100.0 : 0.0; }, 64);
  std::cout << "isolated disc: worst SH9 error " << 100 * err << "% of peak irradiance\n";
  EXPECT_GT(err, 0.03);
  EXPECT_LT(err, 0.08);
}

scene::PatchMesh greyRoomMesh(bool withDesk) {
  scene::RoomDescription room;
  const scene::Material wall{dvec3(0.6), dvec3(0.0)};
  room.addRoomShell({dvec3(0.0), dvec3(4.0, 2.5, 3.0)}, wall, wall, wall);
  if (withDesk) room.addSolidBox("desk", {dvec3(1.0, 0.0, 1.0), dvec3(2.6, 0.9, 2.0)}, wall, false);
  return scene::buildPatchMesh(room, 0.5);
}

TEST(IrradianceVolumeBuild, UniformRoomGivesUniformIrradiance) {
  const scene::PatchMesh mesh = greyRoomMesh(false);
  const EmbreeScene rays(mesh);
  const std::vector<dvec3> radiance(mesh.patches.size(), dvec3(1.0, 2.0, 0.5));
  IrradianceVolumeOptions o;
  o.dims = {6, 4, 5};
  const shadow::IrradianceVolume vol = buildIrradianceVolume(mesh, rays, radiance, o);
  vol.validate();
  for (size_t v = 0; v < vol.vertexCount(); ++v) ASSERT_EQ(vol.valid[v], 1) << v;
  for (const dvec3& n : testNormals()) {
    const glm::vec3 e = vol.irradianceOverPi(glm::vec3(1.3f, 0.7f, 2.1f), glm::vec3(n));
    EXPECT_NEAR(e.x, 1.0, 0.02);
    EXPECT_NEAR(e.y, 2.0, 0.04);
    EXPECT_NEAR(e.z, 0.5, 0.01);
  }
}

TEST(IrradianceVolumeBuild, VerticesInsideSolidsAreInvalid) {
  const scene::PatchMesh mesh = greyRoomMesh(true);
  const EmbreeScene rays(mesh);
  const std::vector<dvec3> radiance(mesh.patches.size(), dvec3(1.0));
  IrradianceVolumeOptions o;
  o.dims = {8, 5, 6};  // spacing 0.5: cell centres at 0.25 + 0.5 i
  const shadow::IrradianceVolume vol = buildIrradianceVolume(mesh, rays, radiance, o);
  size_t inside = 0, invalid = 0;
  for (uint32_t k = 0; k < 6; ++k) {
    for (uint32_t j = 0; j < 5; ++j) {
      for (uint32_t i = 0; i < 8; ++i) {
        const glm::vec3 p = vol.origin + glm::vec3(float(i), float(j), float(k)) * vol.spacing;
        const bool inDesk = p.x > 1.0f && p.x < 2.6f && p.y < 0.9f && p.z > 1.0f && p.z < 2.0f;
        const bool isInvalid = vol.valid[(k * 5 + j) * 8 + i] == 0;
        EXPECT_EQ(inDesk, isInvalid) << i << " " << j << " " << k;
        inside += inDesk;
        invalid += isInvalid;
      }
    }
  }
  EXPECT_GT(inside, 0u);
  // Just above the desk the lookup stays at the room's level: no dark leak from inside.
  const glm::vec3 e = vol.irradianceOverPi(glm::vec3(1.8f, 0.95f, 1.5f), glm::vec3(0, 1, 0));
  EXPECT_NEAR(e.x, 1.0, 0.05);
}

TEST(IrradianceVolumeBuild, SameBytesForAnyThreadCount) {
  scene::RoomDescription room;
  const scene::Material wall{dvec3(0.6, 0.5, 0.4), dvec3(0.0)};
  room.addRoomShell({dvec3(0.0), dvec3(4.0, 2.5, 3.0)}, wall, wall, wall);
  room.quads[1].regions.push_back({"light", 0.4, 0.6, 0.4, 0.6, {dvec3(0.5), dvec3(20.0)}, 0.25});
  room.addSolidBox("desk", {dvec3(1.0, 0.0, 1.0), dvec3(2.6, 0.9, 2.0)}, wall, false);
  const scene::PatchMesh mesh = scene::buildPatchMesh(room, 0.5);
  const EmbreeScene rays(mesh);
  GatherOptions g;
  g.threads = 1;
  const std::vector<dvec3> l1 = solvePatchRadiance(mesh, rays, 2, g);
  g.threads = 3;
  const std::vector<dvec3> l3 = solvePatchRadiance(mesh, rays, 2, g);
  ASSERT_EQ(0, std::memcmp(l1.data(), l3.data(), l1.size() * sizeof(dvec3)));
  IrradianceVolumeOptions o;
  o.dims = {7, 4, 6};
  std::vector<shadow::IrradianceVolume> vols;
  for (unsigned t : {1u, 2u, 3u}) {
    o.threads = t;
    vols.push_back(buildIrradianceVolume(mesh, rays, l1, o));
  }
  for (size_t i = 1; i < vols.size(); ++i) {
    EXPECT_EQ(vols[0].coefficients, vols[i].coefficients);
    EXPECT_EQ(vols[0].valid, vols[i].valid);
    EXPECT_EQ(
        0, std::memcmp(vols[0].fallback.data(), vols[i].fallback.data(), sizeof(vols[0].fallback)));
  }
  // The light is above: upward-facing normals get more than downward ones.
  const glm::vec3 up = vols[0].irradianceOverPi(glm::vec3(2.0f, 1.5f, 1.5f), glm::vec3(0, 1, 0));
  const glm::vec3 down = vols[0].irradianceOverPi(glm::vec3(2.0f, 1.5f, 1.5f), glm::vec3(0, -1, 0));
  EXPECT_GT(up.x, 2 * down.x);
}

TEST(IrradianceVolumeBuild, RejectsBadInput) {
  const scene::PatchMesh mesh = greyRoomMesh(false);
  const EmbreeScene rays(mesh);
  const std::vector<dvec3> radiance(mesh.patches.size(), dvec3(1.0));
  IrradianceVolumeOptions o;
  EXPECT_THROW(buildIrradianceVolume(mesh, rays, std::span(radiance).subspan(1), o),
               std::invalid_argument);
  o.dims = {0, 1, 1};
  EXPECT_THROW(buildIrradianceVolume(mesh, rays, radiance, o), std::invalid_argument);
  o.dims = {2, 2, 2};
  o.directionsPerSide = 0;
  EXPECT_THROW(buildIrradianceVolume(mesh, rays, radiance, o), std::invalid_argument);
}

TEST(PatchRadiosity, DirectLightMatchesTheFormFactorSum) {
  scene::RoomDescription room;
  const scene::Material wall{dvec3(0.5), dvec3(0.0)};
  room.addRoomShell({dvec3(0.0), dvec3(4.0, 2.5, 3.0)}, wall, wall, wall);
  room.quads[1].regions.push_back({"light", 0.4, 0.6, 0.4, 0.6, {dvec3(0.5), dvec3(10.0)}, 0.8});
  const scene::PatchMesh mesh = scene::buildPatchMesh(room, 0.5);
  const EmbreeScene rays(mesh);
  const std::vector<dvec3> l = solvePatchRadiance(mesh, rays, 1);
  for (size_t i = 0; i < mesh.patches.size(); ++i) {
    const scene::Patch& p = mesh.patches[i];
    dvec3 expect = p.emission;
    for (size_t j = 0; j < mesh.patches.size(); ++j) {
      const scene::Patch& q = mesh.patches[j];
      if (j == i || !q.emits()) continue;
      expect += p.reflectance * q.emission *
                scene::pointToPatchFormFactor(p.centre, p.normal, q.centre, q.normal, q.area);
    }
    EXPECT_NEAR(l[i].x, expect.x, 1e-12 + 1e-9 * expect.x) << i;  // empty convex room
  }
  EXPECT_THROW(solvePatchRadiance(mesh, rays, -1), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::lighting
