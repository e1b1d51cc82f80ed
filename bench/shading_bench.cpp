// Product shading (Gibson & Chalmers 2003 §5): building the irradiance volume offline, and
// the per-frame vertex shading from it. Targets (issue 4): a 20x10x20 volume over a
// ~2,000-patch room in <= 2 s on 2 cores; >= 20 M shaded vertices/s.
//   build/dev/bin/penumbra_shading_bench
#include <benchmark/benchmark.h>

#include <vector>

#include "bench/benchmark_main.h"
#include "core/job_pool.h"
#include "lighting/embree_scene.h"
#include "lighting/irradiance_volume_gather.h"
#include "lighting/patch_radiosity.h"
#include "lighting/radiance_transfer.h"
#include "scene/camera.h"
#include "shadow/environment_map.h"
#include "shadow/irradiance_volume.h"
#include "shadow/source_receiver_sets.h"

namespace penumbra {
namespace {

using glm::dvec3;

// The showroom's shell (6 x 3 x 5 m) with a desk, four ceiling lights and a window, at a
// patch size giving about 2,000 patches.
scene::PatchMesh benchRoom() {
  scene::RoomDescription room;
  const scene::Material wall{dvec3(0.7), dvec3(0.0)};
  const uint32_t floor = room.addRoomShell({dvec3(0.0), dvec3(6.0, 3.0, 5.0)},
                                           {dvec3(0.45, 0.38, 0.3), dvec3(0.0)}, wall, wall);
  for (double s : {0.3, 0.6}) {
    for (double t : {0.3, 0.6}) {
      room.quads[floor + 1].regions.push_back(
          {"light", s, s + 0.1, t, t + 0.12, {dvec3(0.5), dvec3(14.0, 13.0, 11.5)}, 0.2});
    }
  }
  room.quads[floor + 5].regions.push_back(
      {"window", 0.15, 0.35, 0.3, 0.7, {dvec3(0.5), dvec3(5.0, 6.0, 7.5)}, 0.2});
  room.addSolidBox("desk", {dvec3(4.4, 0.0, 3.4), dvec3(5.8, 0.75, 4.2)},
                   {dvec3(0.5, 0.33, 0.2), dvec3(0.0)}, false);
  return scene::buildPatchMesh(room, 0.25);
}

void BM_IrradianceVolumeBuild(benchmark::State& state) {
  const scene::PatchMesh mesh = benchRoom();
  const lighting::EmbreeScene rays(mesh);
  const std::vector<dvec3> radiance = lighting::solvePatchRadiance(mesh, rays, 1);
  lighting::IrradianceVolumeOptions o;  // 20 x 10 x 20
  o.threads = static_cast<unsigned>(state.range(0));
  for (auto _ : state) {
    shadow::IrradianceVolume vol = lighting::buildIrradianceVolume(mesh, rays, radiance, o);
    benchmark::DoNotOptimize(vol.coefficients.data());
  }
  state.counters["patches"] = double(mesh.patches.size());
  state.SetItemsProcessed(int64_t(state.iterations()) * 20 * 10 * 20);
}
BENCHMARK(BM_IrradianceVolumeBuild)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The showroom's light transport (Gibson 2003 §4-5): the camera's receiver set and the
// point-to-patch radiance transfers of a 0.7 power share, 2 threads (was printed by
// lighting/radiance_transfer_test.cpp's showroom test).
void BM_ShowroomTransfers(benchmark::State& state) {
  const scene::PatchMesh mesh = benchRoom();
  const lighting::EmbreeScene rays(mesh);
  scene::Camera camera;
  camera.eye = dvec3(0.35, 1.6, 0.35);
  camera.target = dvec3(3.2, 0.7, 2.8);
  camera.fovYDegrees = 60;
  camera.aspect = 640.0 / 480.0;
  camera.zNear = 0.05;
  camera.zFar = 15;
  lighting::TransferOptions options;
  options.threads = 2;
  size_t entries = 0;
  for (auto _ : state) {
    const std::vector<uint8_t> visible =
        lighting::patchesVisibleFromCamera(mesh, rays, camera.viewProj(), 640, 480);
    const shadow::SourceReceiverSets sets = shadow::selectSourcesAndReceivers(mesh, visible, 0.7);
    const shadow::RadianceTransfers t =
        lighting::computeRadianceTransfers(mesh, sets, rays, options);
    entries = t.entryVertex.size();
    benchmark::DoNotOptimize(t.entryTransfer.data());
  }
  state.counters["patches"] = double(mesh.patches.size());
  state.counters["entries"] = double(entries);
}
BENCHMARK(BM_ShowroomTransfers)->Unit(benchmark::kMillisecond)->UseRealTime();

// Per-frame: trilinear SH9 lookup x reflectance, T() per channel, split into contiguous
// blocks over a job pool (each vertex is independent, so the bytes do not depend on it).
void BM_ShadeVertices(benchmark::State& state) {
  const scene::PatchMesh mesh = benchRoom();
  const lighting::EmbreeScene rays(mesh);
  const std::vector<dvec3> radiance = lighting::solvePatchRadiance(mesh, rays, 1);
  lighting::IrradianceVolumeOptions o;
  o.dims = {10, 5, 10};
  const shadow::IrradianceVolume vol = lighting::buildIrradianceVolume(mesh, rays, radiance, o);
  constexpr size_t kVertices = 100000;
  std::vector<core::Vec3> positions(kVertices);
  std::vector<glm::vec3> normals(kVertices);
  for (size_t i = 0; i < kVertices; ++i) {
    const float a = float(i % 1000) / 1000.0f, b = float(i / 1000) / 100.0f;
    positions[i] = {2.0f + a, 0.2f + b, 2.0f + a * b};
    normals[i] = glm::vec3(a - 0.5f, 1.0f - b, b - a);
  }
  std::vector<core::Rgb8> colours(kVertices);
  const shadow::ToneCurve tone = shadow::ToneCurve::gamma(1.2, 2.2);
  core::JobPool pool(static_cast<int>(state.range(0)));
  constexpr size_t kBlock = 4096;
  const size_t blocks = (kVertices + kBlock - 1) / kBlock;
  for (auto _ : state) {
    pool.parallelFor(blocks, [&](size_t blk, int) {
      const size_t first = blk * kBlock, count = std::min(kBlock, kVertices - first);
      shadow::shadeVerticesDiffuse(
          vol, std::span(positions).subspan(first, count), std::span(normals).subspan(first, count),
          glm::vec3(0.6f, 0.4f, 0.3f), tone, std::span(colours).subspan(first, count), {});
    });
    benchmark::DoNotOptimize(colours.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(kVertices));
}
BENCHMARK(BM_ShadeVertices)->Arg(1)->Arg(2)->UseRealTime();

// Per product move (§5, Fig. 9): the six 32x32 faces of the environment map, then the
// Phong lobe (32 lookups) for 1,000 vertices.
void BM_EnvironmentMapAndSpecular(benchmark::State& state) {
  const scene::PatchMesh mesh = benchRoom();
  const lighting::EmbreeScene rays(mesh);
  const std::vector<dvec3> radiance = lighting::solvePatchRadiance(mesh, rays, 1);
  std::vector<glm::vec3> patchRadiance(radiance.begin(), radiance.end());
  const shadow::ToneCurve tone = shadow::ToneCurve::gamma(1.2, 2.2);
  const shadow::ToneInverse inverse(tone);
  const raster::ShadedMesh room =
      shadow::roomForEnvironment(mesh.toRasterMesh(), mesh.trianglePatch, patchRadiance, tone);
  const shadow::PhongLobe lobe(130.0f);
  shadow::CubeEnvironmentMap map;
  for (auto _ : state) {
    shadow::renderEnvironmentMap(room, glm::vec3(3.0f, 0.6f, 2.5f), 32, 20.0f, map);
    glm::vec3 sum(0.0f);
    for (int v = 0; v < 1000; ++v) {
      const float a = float(v) * 0.001f;
      sum += shadow::specularRadiance(map, inverse, lobe, glm::vec3(3.0f, 0.5f + a * 0.2f, 2.5f),
                                      glm::vec3(a - 0.5f, 1.0f - a, 0.3f),
                                      glm::vec3(0.35f, 1.6f, 0.35f));
    }
    benchmark::DoNotOptimize(sum);
  }
}
BENCHMARK(BM_EnvironmentMapAndSpecular)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace penumbra

int main(int argc, char** argv) {
  return penumbra::bench::benchmarkMain("penumbra_shading_bench", argc, argv);
}
