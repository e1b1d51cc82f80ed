#include "raster/adversarial_trace.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "core/random.h"
#include "raster/triangle_setup.h"

namespace penumbra::raster {
namespace {

using D3 = std::array<double, 3>;

// Draws of one trace: draw n of the stream keyed by the seed (core/random.h), in program
// order, so the trace is a pure function of the seed.
class Draws {
 public:
  explicit Draws(uint64_t seed) : key_(core::splitmix64(seed ^ 0xAD5E7A11ull)) {}
  double uniform() { return core::unitSample(key_, counter_++); }
  double range(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // An integer in [lo, hi].
  int integer(int lo, int hi) {
    const int n = lo + static_cast<int>(uniform() * static_cast<double>(hi - lo + 1));
    return std::min(n, hi);
  }
  bool chance(double p) { return uniform() < p; }
  uint8_t level(int lo, int hi) { return static_cast<uint8_t>(integer(lo, hi)); }

 private:
  uint64_t key_;
  uint64_t counter_ = 0;
};

D3 sub(const D3& a, const D3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
D3 add(const D3& a, const D3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
D3 scale(const D3& a, double s) {
  return {a[0] * s, a[1] * s, a[2] * s};
}
double dot(const D3& a, const D3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
D3 cross(const D3& a, const D3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
D3 normalise(const D3& a) {
  return scale(a, 1.0 / std::sqrt(dot(a, a)));  // sqrt is correctly rounded (IEEE)
}
core::Vec3 toVec(const D3& a) {
  return {static_cast<float>(a[0]), static_cast<float>(a[1]), static_cast<float>(a[2])};
}

// A grid of n x m quads spanning corner + i du + j dv, two triangles each.
void addGrid(core::Mesh& mesh, const D3& corner, const D3& du, const D3& dv, int n, int m) {
  const auto base = static_cast<uint32_t>(mesh.positions.size());
  for (int j = 0; j <= m; ++j) {
    for (int i = 0; i <= n; ++i)
      mesh.positions.push_back(toVec(add(corner, add(scale(du, i), scale(dv, j)))));
  }
  const auto un = static_cast<uint32_t>(n);
  for (uint32_t j = 0; j < static_cast<uint32_t>(m); ++j) {
    for (uint32_t i = 0; i < un; ++i) {
      const uint32_t a = base + j * (un + 1) + i, b = a + 1, c = a + un + 1, d = c + 1;
      mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
    }
  }
}

core::Mesh box(const D3& lo, const D3& hi) {
  core::Mesh mesh;
  for (int k = 0; k < 8; ++k) {
    mesh.positions.push_back(
        toVec({(k & 1) ? hi[0] : lo[0], (k & 2) ? hi[1] : lo[1], (k & 4) ? hi[2] : lo[2]}));
  }
  mesh.indices = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                  2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  return mesh;
}

void addTriangle(core::Mesh& mesh, const D3& a, const D3& b, const D3& c) {
  const auto base = static_cast<uint32_t>(mesh.positions.size());
  for (const D3* p : {&a, &b, &c}) mesh.positions.push_back(toVec(*p));
  mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2});
}

D3 randomPoint(Draws& r, const D3& lo, const D3& hi) {
  return {r.range(lo[0], hi[0]), r.range(lo[1], hi[1]), r.range(lo[2], hi[2])};
}

}  // namespace

core::Mat4 lookAtPerspective(const std::array<double, 3>& eye, const std::array<double, 3>& at,
                             double focal, double aspect, double zNear, double zFar) {
  const D3 f = normalise(sub(at, eye));
  const D3 s = normalise(cross(f, {0, 1, 0}));
  const D3 u = cross(s, f);
  const double view[16] = {s[0],  s[1],  s[2],  -dot(s, eye),  //
                           u[0],  u[1],  u[2],  -dot(u, eye),  //
                           -f[0], -f[1], -f[2], dot(f, eye),   //
                           0,     0,     0,     1};
  const double proj[16] = {focal / aspect,
                           0,
                           0,
                           0,
                           0,
                           focal,
                           0,
                           0,
                           0,
                           0,
                           (zFar + zNear) / (zNear - zFar),
                           2 * zFar * zNear / (zNear - zFar),
                           0,
                           0,
                           -1,
                           0};
  core::Mat4 m;
  for (size_t r = 0; r < 4; ++r) {
    for (size_t c = 0; c < 4; ++c) {
      double sum = 0;
      for (size_t k = 0; k < 4; ++k) sum += proj[4 * r + k] * view[4 * k + c];
      m.m[4 * r + c] = static_cast<float>(sum);
    }
  }
  return m;
}

FrameTrace adversarialTrace(uint64_t seed) {
  Draws r(seed);
  FrameTrace trace;
  StaticView& view = trace.view;
  constexpr std::array<uint32_t, 5> kWidths = {128, 160, 192, 256, 320};
  constexpr std::array<uint32_t, 5> kHeights = {96, 120, 144, 192, 240};
  view.width = kWidths[static_cast<size_t>(r.integer(0, 4))];
  view.height = kHeights[static_cast<size_t>(r.integer(0, 4))];
  const D3 eye = {r.range(-1.5, 1.5), r.range(1.2, 3.0), r.range(3.5, 6.0)};
  const D3 at = {r.range(-0.5, 0.5), r.range(0.0, 1.0), r.range(-1.0, 0.5)};
  const double cameraNear = r.range(0.2, 0.8);
  view.cameraViewProj =
      lookAtPerspective(eye, at, r.range(0.9, 1.8), static_cast<double>(view.width) / view.height,
                        cameraNear, r.range(8.0, 30.0));

  // The room: a floor reaching behind the eye (its triangles there cross w = 0 and the near
  // plane: spec §3), a back wall, and loose triangles, some with a vertex behind the eye.
  core::Mesh& mesh = view.staticMesh;
  const int floorN = r.integer(3, 9), wallN = r.integer(2, 6);
  addGrid(mesh, {-6, 0, -5}, {12.0 / floorN, 0, 0}, {0, 0, 14.0 / floorN}, floorN, floorN);
  addGrid(mesh, {-6, 0, -5}, {12.0 / wallN, 0, 0}, {0, 4.0 / wallN, 0}, wallN, wallN);
  const D3 back = normalise(sub(eye, at));
  const int loose = r.integer(4, 10);
  for (int k = 0; k < loose; ++k) {
    const D3 a = randomPoint(r, {-4, 0, -4}, {4, 3, 4});
    const D3 b = randomPoint(r, {-4, 0, -4}, {4, 3, 4});
    D3 c = randomPoint(r, {-4, 0, -4}, {4, 3, 4});
    if (r.chance(0.5)) {
      c = add(add(eye, scale(back, r.range(0.2, 2.0))), randomPoint(r, {-1, -1, -1}, {1, 1, 1}));
    }
    addTriangle(mesh, a, b, c);
  }
  // Coplanar duplicates: the same three vertex indices once more, later in the mesh.
  const auto original = static_cast<uint32_t>(mesh.triangleCount());
  std::vector<std::pair<uint32_t, uint32_t>> duplicates;
  const int duplicateCount = r.integer(3, 8);
  for (int k = 0; k < duplicateCount; ++k) {
    const auto t = static_cast<uint32_t>(r.integer(0, static_cast<int>(original) - 1));
    const auto copy = static_cast<uint32_t>(mesh.triangleCount());
    for (uint32_t i = 0; i < 3; ++i) mesh.indices.push_back(mesh.indices[3 * t + i]);
    duplicates.emplace_back(t, copy);
  }
  const auto staticTriangles = static_cast<uint32_t>(mesh.triangleCount());

  FrameContent& frame = trace.frame;
  frame.background.resize(static_cast<size_t>(view.width) * view.height * 4);
  const uint64_t pixelKey = core::splitmix64(seed + 0x6B61ull);
  for (size_t i = 0; i < frame.background.size(); ++i) {
    const double u = core::unitSample(pixelKey, i);
    frame.background[i] = static_cast<uint8_t>(i % 4 == 3 ? 200 + u * 55 : 60 + u * 195);
  }

  // The product on the floor, and sometimes a second one across the camera's near plane.
  const D3 centre = {r.range(-1.5, 1.5), 0, r.range(-2.0, 1.5)};
  const double half = r.range(0.25, 0.6), height = r.range(0.5, 1.4);
  const D3 lo = {centre[0] - half, 0, centre[2] - half};
  const D3 hi = {centre[0] + half, height, centre[2] + half};
  auto shaded = [&](const core::Mesh& m) {
    ShadedMesh o;
    o.mesh = m;
    for (size_t k = 0; k < m.positions.size(); ++k) {
      o.colours.push_back({r.level(0, 255), r.level(0, 255), r.level(0, 255)});
    }
    return o;
  };
  frame.objects.push_back(shaded(box(lo, hi)));
  if (r.chance(0.4)) {
    // Off the axis, so that it hides a corner of the view rather than all of it.
    const D3 right = normalise(cross(back, {0, 1, 0}));
    const D3 nearCentre =
        add(sub(eye, scale(back, cameraNear)), add(scale(right, r.range(-0.3, 0.3) * cameraNear),
                                                   {0, r.range(-0.3, 0.3) * cameraNear, 0}));
    const double s = 0.1 * cameraNear;
    frame.objects.push_back(shaded(box(sub(nearCentre, {s, s, s}), add(nearCentre, {s, s, s}))));
  }

  // Occluders: the product's proxy, and the proxy with long triangles that cross the lights'
  // near and far planes.
  // A canopy over the floor beside the product (never drawn in the frame: occluders only
  // cast) gives every light a shadow the camera sees, wherever the light stands.
  const D3 canopy = {centre[0] + r.range(-1.5, 1.5), r.range(1.2, 1.8),
                     centre[2] + r.range(-1.0, 1.0)};
  const double canopyHalf = r.range(0.6, 1.2);
  core::Mesh proxy = box(lo, hi);
  const core::Mesh roof =
      box(sub(canopy, {canopyHalf, 0.05, canopyHalf}), add(canopy, {canopyHalf, 0.05, canopyHalf}));
  for (const uint32_t i : roof.indices)
    proxy.indices.push_back(i + static_cast<uint32_t>(proxy.positions.size()));
  proxy.positions.insert(proxy.positions.end(), roof.positions.begin(), roof.positions.end());
  frame.occluders.push_back(proxy);
  core::Mesh wide = proxy;
  const int wideCount = r.integer(2, 5);
  for (int k = 0; k < wideCount; ++k) {
    addTriangle(wide, randomPoint(r, {-6, 0.1, -6}, {6, 6, 6}),
                randomPoint(r, {-6, 0.1, -6}, {6, 6, 6}), randomPoint(r, {-1, 0.2, -1}, {1, 2, 1}));
  }
  frame.occluders.push_back(wide);

  const int passCount = r.integer(2, 6);
  for (int p = 0; p < passCount; ++p) {
    ShadowPass pass;
    // Aimed between the product and the floor under the canopy: both shadows in the map.
    const D3 between = {0.5 * (centre[0] + canopy[0]), 0, 0.5 * (centre[2] + canopy[2])};
    const D3 target = add(between, randomPoint(r, {-0.5, 0, -0.5}, {0.5, 0.8, 0.5}));
    D3 light = {r.range(-4, 4), r.range(2, 5), r.range(-4, 4)};
    if (std::fabs(light[0] - target[0]) < 0.7 && std::fabs(light[2] - target[2]) < 0.7) {
      light[0] = target[0] + 1.5;  // keep the look direction away from the up vector
    }
    const double distance = std::sqrt(dot(sub(target, light), sub(target, light)));
    const double lightNear = r.range(0.1, 1.0);
    // Half the lights end a little past their target: the floor farther away lies beyond
    // the far plane (d > 1 against texels the occluder never wrote).
    double lightFar = r.chance(0.5) ? distance * r.range(1.0, 1.4) : r.range(15, 30);
    lightFar = std::max(lightFar, lightNear + 0.5);
    pass.lightViewProj =
        lookAtPerspective(light, target, r.range(0.5, 2.5), 1.0, lightNear, lightFar);
    pass.shadowMapSize = 16 * static_cast<uint32_t>(r.integer(1, 16));
    pass.depthBias = static_cast<float>(r.chance(0.5) ? r.range(-0.03, -0.0005) : r.range(0, 0.01));
    pass.pcf2x2 = r.chance(0.5);
    pass.occluder = static_cast<uint32_t>(r.integer(0, 1));
    // Every third pass culls (not drawn from the stream, so the traces stay as they were).
    pass.cullBackFaces = p % 3 == 2;
    std::vector<uint8_t> listed(staticTriangles, 0);
    for (uint32_t t = 0; t < staticTriangles; ++t) listed[t] = r.chance(0.7) ? 1 : 0;
    for (const auto& [t, copy] : duplicates) {
      if (r.chance(0.8)) listed[t] = listed[copy] = 1;
    }
    for (uint32_t t = 0; t < staticTriangles; ++t) {
      if (listed[t] == 0) continue;
      pass.receiverTriangles.push_back(t);
      for (int k = 0; k < 3; ++k) {
        pass.receiverS.push_back(
            core::Rgb16::fromLevels({r.level(10, 255), r.level(10, 255), r.level(10, 255)}));
      }
    }
    // Self-shadowing (Gibson 2003 §7.2): half the passes shade the product's own faces too,
    // with their own bias, negative in half of those.
    if (r.chance(0.5)) {
      for (uint32_t g = 0; g < frame.objects[0].mesh.triangleCount(); ++g) {
        pass.objectTriangles.push_back(g);
        for (int k = 0; k < 3; ++k) {
          pass.objectS.push_back(
              core::Rgb16::fromLevels({r.level(10, 255), r.level(10, 255), r.level(10, 255)}));
        }
      }
      pass.objectDepthBias =
          static_cast<float>(r.chance(0.5) ? r.range(-0.02, -0.0005) : r.range(0, 0.02));
    }
    frame.passes.push_back(std::move(pass));
  }
  frame.accumulation = Accumulation::kU8;
  validateTrace(trace, "adversarial trace");
  return trace;
}

AdversarialFeatures adversarialFeatures(const FrameTrace& trace) {
  AdversarialFeatures f;
  const core::Mesh& mesh = trace.view.staticMesh;
  for (const ShadowPass& pass : trace.frame.passes) {
    if (pass.depthBias < 0.0f) ++f.negativeBiasPasses;
    if (pass.pcf2x2) ++f.pcfPasses;
    if (!pass.objectTriangles.empty()) ++f.objectReceiverPasses;
    std::map<std::array<uint32_t, 3>, size_t> seen;
    for (const uint32_t t : pass.receiverTriangles) {
      bool behind = false, beyond = false, outside = false;
      std::array<uint32_t, 3> key{};
      for (size_t k = 0; k < 3; ++k) {
        key[k] = mesh.indices[3 * t + k];
        const core::Vec3& p = mesh.positions[key[k]];
        const ClipVertex c = transformPoint(trace.view.cameraViewProj, p);
        const ClipVertex l = transformPoint(pass.lightViewProj, p);
        behind = behind || !(c.w > 0.0f);
        beyond = beyond || (l.w > 0.0f && l.z > l.w);
        outside = outside || (l.w > 0.0f && (std::fabs(l.x) > l.w || std::fabs(l.y) > l.w));
      }
      f.behindEye += behind ? 1 : 0;
      f.beyondLightFar += beyond ? 1 : 0;
      f.outsideLightMap += outside ? 1 : 0;
      f.duplicatePairs += seen[key]++;
    }
  }
  return f;
}

}  // namespace penumbra::raster
