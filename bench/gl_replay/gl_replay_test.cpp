// Whole frames: GlTraceReplay (OpenGL ES 3 on llvmpipe) against raster::Renderer on a
// trace built here, and on the recorded traces in data/traces/ once there are any.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "bench/gl_replay/gl_test_context.h"
#include "bench/gl_replay/gl_trace_replay.h"
#include "bench/gl_replay/image_compare.h"
#include "raster/adversarial_trace.h"
#include "raster/frame_trace.h"
#include "raster/renderer.h"
#include "simd/targets.h"

namespace penumbra::gl {
namespace {

using core::Mat4;
using core::Mesh;
using core::Rgb8;
using core::Vec3;
using raster::FrameTrace;
using D3 = std::array<double, 3>;

// The camera and lights of the built-in traces: a field of view in degrees.
core::Mat4 viewProj(const D3& eye, const D3& at, double fovyDeg, double aspect, double zNear,
                    double zFar) {
  const double focal = 1.0 / std::tan(fovyDeg * 3.14159265358979323846 / 360.0);
  return raster::lookAtPerspective(eye, at, focal, aspect, zNear, zFar);
}

// A grid of n x m quads spanning corner + i*du + j*dv, two triangles each.
void addGrid(core::Mesh& mesh, const core::Vec3& corner, const core::Vec3& du, const core::Vec3& dv,
             uint32_t n, uint32_t m) {
  const auto base = static_cast<uint32_t>(mesh.positions.size());
  for (uint32_t j = 0; j <= m; ++j) {
    for (uint32_t i = 0; i <= n; ++i) {
      const auto fi = static_cast<float>(i), fj = static_cast<float>(j);
      mesh.positions.push_back({corner.x + fi * du.x + fj * dv.x, corner.y + fi * du.y + fj * dv.y,
                                corner.z + fi * du.z + fj * dv.z});
    }
  }
  for (uint32_t j = 0; j < m; ++j) {
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t a = base + j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
    }
  }
}

core::Mesh box(const core::Vec3& lo, const core::Vec3& hi) {
  core::Mesh mesh;
  for (int k = 0; k < 8; ++k) {
    mesh.positions.push_back({(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z});
  }
  mesh.indices = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                  2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  return mesh;
}

// A floor and a back wall (receivers, `grid` quads per 8 m), a shaded box standing on the
// floor, its proxy as occluder, and two passes: a binary one and a 2x2 PCF one from
// another source.
FrameTrace builtInTrace(uint32_t width = 256, uint32_t height = 192, uint32_t grid = 8) {
  FrameTrace trace;
  raster::StaticView& view = trace.view;
  view.width = width;
  view.height = height;
  view.cameraViewProj =
      viewProj({0.7, 3.2, 5.5}, {0, 0.4, 0}, 50, static_cast<double>(width) / height, 0.5, 30);
  const float step = 8.0f / static_cast<float>(grid);
  addGrid(view.staticMesh, {-4, 0, -4}, {step, 0, 0}, {0, 0, step}, grid, grid);
  addGrid(view.staticMesh, {-4, 0, -4}, {step, 0, 0}, {0, step, 0}, grid, grid / 2);
  const auto staticTriangles = static_cast<uint32_t>(view.staticMesh.triangleCount());

  raster::FrameContent& frame = trace.frame;
  frame.background.resize(static_cast<size_t>(view.width) * view.height * 4);
  for (uint32_t y = 0; y < view.height; ++y) {
    for (uint32_t x = 0; x < view.width; ++x) {
      uint8_t* p = &frame.background[(static_cast<size_t>(y) * view.width + x) * 4];
      p[0] = static_cast<uint8_t>(120 + (x * 97 + y * 13) % 120);
      p[1] = static_cast<uint8_t>(100 + (x * 7 + y * 61) % 140);
      p[2] = static_cast<uint8_t>(90 + (x ^ y) % 150);
      p[3] = static_cast<uint8_t>(200 + (x + y) % 56);
    }
  }
  raster::ShadedMesh object;
  object.mesh = box({-0.6f, 0.0f, -0.4f}, {0.5f, 1.1f, 0.6f});
  for (size_t k = 0; k < object.mesh.positions.size(); ++k) {
    object.colours.push_back({static_cast<uint8_t>(60 + 23 * k), static_cast<uint8_t>(200 - 17 * k),
                              static_cast<uint8_t>(90 + 11 * k)});
  }
  frame.objects.push_back(object);
  frame.occluders.push_back(box({-0.6f, 0.0f, -0.4f}, {0.5f, 1.1f, 0.6f}));

  auto pass = [&](const D3& light, uint32_t size, float bias, bool pcf, int salt) {
    raster::ShadowPass p;
    p.lightViewProj = viewProj(light, {0, 0, 0}, 100, 1.0, 0.5, 30);
    p.shadowMapSize = size;
    p.depthBias = bias;
    p.pcf2x2 = pcf;
    p.occluder = 0;
    for (uint32_t t = 0; t < staticTriangles; ++t) {
      if ((t + static_cast<uint32_t>(salt)) % 7 == 0) continue;  // not every triangle
      p.receiverTriangles.push_back(t);
      for (uint32_t k = 0; k < 3; ++k) {
        p.receiverS.push_back(
            core::Rgb16::fromLevels({static_cast<uint8_t>(40 + (t * 7 + k * 31 + salt) % 90),
                                     static_cast<uint8_t>(30 + (t * 11 + k * 13) % 100),
                                     static_cast<uint8_t>(50 + (t * 5 + k * 17 + salt) % 70)}));
      }
    }
    frame.passes.push_back(p);
  };
  pass({3.0, 2.6, 2.2}, 256, 0.002f, false, 0);
  pass({-3.2, 2.2, 1.5}, 128, 0.003f, true, 3);
  raster::validateTrace(trace, "built-in GL test trace");
  return trace;
}

struct Agreement {
  ImageDiff diff;
  std::vector<uint8_t> gl, ours;
};

Agreement compareOnce(const FrameTrace& trace) {
  Agreement a;
  a.gl.resize(static_cast<size_t>(trace.view.width) * trace.view.height * 4);
  a.ours.resize(a.gl.size());
  GlTraceReplay replay(trace.view);
  replay.render(trace.frame, a.gl);
  raster::RenderOptions options;
  options.isa = simd::bestIsa();
  options.threads = 2;
  raster::Renderer renderer(trace.view, options);
  renderer.render(trace.frame, a.ours);
  a.diff = compareImages(a.gl, a.ours, trace.view.width, trace.view.height);
  return a;
}

void report(const std::string& name, const ImageDiff& d) {
  std::cout << "[ composite ] " << name << ": identical_byte_share " << d.identicalByteShare
            << ", max_abs_diff " << d.maxAbsDiff << " (shift-tolerant " << d.maxAbsDiffShiftTolerant
            << "), mean_abs_diff " << d.meanAbsDiff << ", differing pixels " << d.differingPixels
            << "\n";
}

// Thresholds: the replay follows spec §2–7 (gl_trace_replay.h) and is byte-identical on
// every trace we have; what is left to llvmpipe (docs/performance.md, "Where the GL replay
// cannot follow the spec") could move single pixels on another driver, so a share is
// required, not identity. Before the replay followed the spec these traces reached 0.997.
void expectAgreement(const ImageDiff& d) {
  EXPECT_GE(d.identicalByteShare, 0.999);
  EXPECT_LE(d.meanAbsDiff, 0.05);
  EXPECT_LE(d.maxAbsDiffShiftTolerant, 16);
}

TEST(GlReplay, WindowToTexelMatchesLightTransform) {
  // A world point through camera -> window, then P, lands where the light matrix puts it.
  const core::Mat4 camera = viewProj({0.7, 3.2, 5.5}, {0, 0.4, 0}, 50, 256.0 / 192.0, 0.5, 30);
  const core::Mat4 light = viewProj({2.5, 6.0, 2.0}, {0, 0, 0}, 100, 1.0, 0.5, 30);
  const core::Mat4 p = windowToLightTexel(camera, 256, 192, light, 256);
  const double pt[4] = {0.3, 0.2, -0.7, 1};
  auto apply = [](const core::Mat4& m, const double* v, double* out) {
    for (size_t r = 0; r < 4; ++r) {
      out[r] = 0;
      for (size_t c = 0; c < 4; ++c) out[r] += double{m.m[4 * r + c]} * v[c];
    }
  };
  double c[4], l[4], q[4];
  apply(camera, pt, c);
  apply(light, pt, l);
  const double window[4] = {(c[0] / c[3] + 1) * 128, (1 - c[1] / c[3]) * 96,
                            c[2] / c[3] * 0.5 + 0.5, 1};
  apply(p, window, q);
  EXPECT_NEAR(q[0] / q[3], (l[0] / l[3] + 1) * 128, 1e-2);
  EXPECT_NEAR(q[1] / q[3], (1 - l[1] / l[3]) * 128, 1e-2);
  EXPECT_NEAR(q[2] / q[3], l[2] / l[3] * 0.5 + 0.5, 1e-4);
}

TEST(GlReplay, CompositeAgreesOnBuiltInTrace) {
  PENUMBRA_REQUIRE_GL();
  const FrameTrace trace = builtInTrace();
  const Agreement a = compareOnce(trace);
  report("built-in trace 256x192, 2 passes", a.diff);
  RecordProperty("identical_byte_share", std::to_string(a.diff.identicalByteShare));
  RecordProperty("max_abs_diff", a.diff.maxAbsDiff);
  expectAgreement(a.diff);
  // Alpha is never touched by the passes and comes from the background or objects.
  for (size_t i = 3; i < a.gl.size(); i += 4) {
    ASSERT_EQ(a.gl[i], a.ours[i]) << "alpha differs at byte " << i;
  }
}

TEST(GlReplay, CompositeAgreesOnFinerVgaTrace) {
  PENUMBRA_REQUIRE_GL();
  const FrameTrace trace = builtInTrace(640, 480, 48);
  const Agreement a = compareOnce(trace);
  report("built-in trace 640x480, 6912 static triangles, 2 passes", a.diff);
  expectAgreement(a.diff);
}

TEST(GlReplay, CompositeAgreesOnRecordedTraces) {
  PENUMBRA_REQUIRE_GL();
  const std::filesystem::path dir = std::filesystem::path(PENUMBRA_DATA_DIR) / "traces";
  std::vector<std::filesystem::path> traces;
  if (std::filesystem::is_directory(dir)) {
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      if (entry.path().extension() == ".json") traces.push_back(entry.path());
    }
  }
  if (traces.empty()) GTEST_SKIP() << "no traces in " << dir.string() << " yet";
  std::sort(traces.begin(), traces.end());
  // All of them, the 720p and 1080p showroom included: about a second each on llvmpipe.
  for (const auto& path : traces) {
    SCOPED_TRACE(path.string());
    const FrameTrace trace = raster::loadTrace(path);
    const Agreement a = compareOnce(trace);
    report(path.filename().string(), a.diff);
    expectAgreement(a.diff);
  }
}

// Issue 13 item 4: the replay as a faithful second implementation on the traces built to
// part the two (raster/adversarial_trace.h: clipping behind the eye, receivers beyond a
// light's far plane and outside its map, negative bias, coplanar duplicate receivers).
// Before the replay followed the spec this median was 0.75 (docs/performance.md).
TEST(GlReplay, CompositeAgreesOnAdversarialTraces) {
  PENUMBRA_REQUIRE_GL();
  std::vector<double> shares;
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const FrameTrace trace = raster::adversarialTrace(seed);
    const Agreement a = compareOnce(trace);
    report("adversarial seed " + std::to_string(seed), a.diff);
    // The passes must change the frame, or agreeing would say nothing about them.
    FrameTrace unshadowed = trace;
    unshadowed.frame.passes.clear();
    const Agreement base = compareOnce(unshadowed);
    EXPECT_NE(base.ours, a.ours);
    EXPECT_GE(a.diff.identicalByteShare, 0.999);
    shares.push_back(a.diff.identicalByteShare);
  }
  std::sort(shares.begin(), shares.end());
  EXPECT_GE(0.5 * (shares[5] + shares[6]), 0.9999);
}

}  // namespace
}  // namespace penumbra::gl
