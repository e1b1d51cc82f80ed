#include "tests/test_scenes.h"

#include <glm/glm.hpp>

#include "scene/camera.h"

namespace penumbra::testing {
namespace {

// SplitMix64: a counter-based generator, so scenes depend only on the seed.
uint64_t mix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

void addQuad(core::Mesh& m, core::Vec3 a, core::Vec3 b, core::Vec3 c, core::Vec3 d) {
  const uint32_t base = static_cast<uint32_t>(m.positions.size());
  m.positions.insert(m.positions.end(), {a, b, c, d});
  m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

core::Mesh box(float cx, float cy, float cz, float h) {
  core::Mesh m;
  const float x0 = cx - h, x1 = cx + h, y0 = cy - h, y1 = cy + h, z0 = cz - h, z1 = cz + h;
  addQuad(m, {x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1});
  addQuad(m, {x1, y0, z0}, {x0, y0, z0}, {x0, y1, z0}, {x1, y1, z0});
  addQuad(m, {x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}, {x0, y1, z0});
  addQuad(m, {x1, y0, z1}, {x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1});
  addQuad(m, {x0, y1, z1}, {x1, y1, z1}, {x1, y1, z0}, {x0, y1, z0});
  addQuad(m, {x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1});
  return m;
}

}  // namespace

raster::FrameTrace makeTestScene(const TestSceneOptions& o) {
  raster::FrameTrace t;
  t.view.width = o.width;
  t.view.height = o.height;
  scene::Camera camera;
  camera.eye = {0.3, 1.4, 3.0};
  camera.target = {0.0, 0.2, 0.0};
  camera.aspect = double(o.width) / o.height;
  camera.zNear = 0.1;
  camera.zFar = 20.0;
  t.view.cameraViewProj = camera.rasterViewProj();

  // Floor [-2, 2]^2 at y = 0 and a back wall at z = -2.
  core::Mesh& room = t.view.staticMesh;
  const int n = o.floorCells;
  const float step = 4.0f / static_cast<float>(n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const float x0 = -2.0f + step * static_cast<float>(i),
                  z0 = -2.0f + step * static_cast<float>(j);
      addQuad(room, {x0, 0, z0 + step}, {x0 + step, 0, z0 + step}, {x0 + step, 0, z0}, {x0, 0, z0});
    }
  }
  for (int j = 0; j < n / 2; ++j) {
    for (int i = 0; i < n; ++i) {
      const float x0 = -2.0f + step * static_cast<float>(i), y0 = step * static_cast<float>(j);
      addQuad(room, {x0, y0, -2}, {x0 + step, y0, -2}, {x0 + step, y0 + step, -2},
              {x0, y0 + step, -2});
    }
  }

  t.frame.background.resize(size_t{o.width} * o.height * 4);
  for (uint32_t y = 0; y < o.height; ++y) {
    for (uint32_t x = 0; x < o.width; ++x) {
      uint8_t* p = &t.frame.background[4 * (size_t{o.width} * y + x)];
      p[0] = static_cast<uint8_t>(120 + (x * 97 / o.width));
      p[1] = static_cast<uint8_t>(110 + (y * 89 / o.height));
      p[2] = static_cast<uint8_t>(100 + ((x + y) % 37));
      p[3] = 255;
    }
  }

  const float h = 0.3f;
  core::Mesh object = box(o.objectOffsetX, h, 0.0f, h);
  if (o.objectVisible) {
    raster::ShadedMesh shaded{object, {}};
    for (size_t i = 0; i < object.positions.size(); ++i) {
      const uint64_t r = mix(o.seed * 1000 + i);
      shaded.colours.push_back({static_cast<uint8_t>(60 + r % 120),
                                static_cast<uint8_t>(40 + (r >> 8) % 120),
                                static_cast<uint8_t>(30 + (r >> 16) % 120)});
    }
    t.frame.objects.push_back(shaded);
  }
  t.frame.occluders.push_back(object);

  for (int p = 0; p < o.passes; ++p) {
    const double angle = 0.9 * p;
    const glm::dvec3 light{1.2 * std::cos(angle), 2.4 + 0.1 * p, 1.2 * std::sin(angle)};
    scene::Camera lightCamera;
    lightCamera.eye = light;
    lightCamera.target = {o.objectOffsetX, h, 0.0};
    lightCamera.up = {0, 0, 1};
    lightCamera.fovYDegrees = 40;
    lightCamera.aspect = 1.0;
    lightCamera.zNear = 0.5;
    lightCamera.zFar = 10.0;
    raster::ShadowPass pass;
    pass.lightViewProj = lightCamera.rasterViewProj();
    pass.shadowMapSize = p % 2 == 0 ? 128 : 64;
    pass.depthBias = 0.002f;
    pass.pcf2x2 = o.pcf2x2 || p % 3 == 2;
    pass.occluder = 0;
    for (uint32_t tri = 0; tri < room.triangleCount(); ++tri) {
      if (mix(o.seed + 7919u * tri + static_cast<uint64_t>(p)) % 5 == 0)
        continue;  // not every receiver
      pass.receiverTriangles.push_back(tri);
      for (int c = 0; c < 3; ++c) {
        const uint64_t r = mix((o.seed << 20) + tri * 3u + static_cast<uint64_t>(c) +
                               100000u * static_cast<uint64_t>(p));
        pass.receiverS.push_back(core::Rgb16::fromLevels({static_cast<uint8_t>(r % 41),
                                                          static_cast<uint8_t>((r >> 8) % 41),
                                                          static_cast<uint8_t>((r >> 16) % 41)}));
      }
    }
    // Self-shadowing receivers (§7.2): every object triangle, S from the same hash.
    if (o.objectVisible) {
      pass.objectDepthBias = 0.01f;
      for (uint32_t tri = 0; tri < object.triangleCount(); ++tri) {
        pass.objectTriangles.push_back(tri);
        for (int c = 0; c < 3; ++c) {
          const uint64_t r = mix((o.seed << 24) + tri * 3u + static_cast<uint64_t>(c) +
                                 7777u * static_cast<uint64_t>(p));
          pass.objectS.push_back(core::Rgb16::fromLevels({static_cast<uint8_t>(r % 31),
                                                          static_cast<uint8_t>((r >> 8) % 31),
                                                          static_cast<uint8_t>((r >> 16) % 31)}));
        }
      }
    }
    t.frame.passes.push_back(std::move(pass));
  }
  raster::validateTrace(t, "test scene");
  return t;
}

}  // namespace penumbra::testing
