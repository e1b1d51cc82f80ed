#include "shadow/synthetic_traces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/camera.h"
#include "scene/patch_mesh.h"
#include "shadow/intensity_transfer.h"
#include "shadow/light_frustum.h"
#include "shadow/patch_transfer.h"

namespace penumbra::shadow {
namespace {

using core::Rgb8;
using glm::dvec3;

constexpr uint64_t kSetSeed = 0x50454E554D425241ull;  // "PENUMBRA": fixed, for reproducible sets

double luminance(const dvec3& c) {
  return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}

// ---------------------------------------------------------------------------------------
// Synthetic objects: small indexed meshes with per-vertex normals.

struct ObjectMesh {
  std::vector<dvec3> positions, normals;
  std::vector<uint32_t> indices;

  uint32_t vertex(const dvec3& p, const dvec3& n) {
    positions.push_back(p);
    normals.push_back(n);
    return static_cast<uint32_t>(positions.size() - 1);
  }
  void tri(uint32_t a, uint32_t b, uint32_t c) { indices.insert(indices.end(), {a, b, c}); }

  // Six flat faces, 12 triangles (vertices not shared between faces: flat normals).
  void addBox(const scene::Aabb& b) {
    const dvec3 lo = b.min, hi = b.max;
    for (int axis = 0; axis < 3; ++axis) {
      for (int side = 0; side < 2; ++side) {
        dvec3 n(0.0);
        n[axis] = side == 0 ? -1.0 : 1.0;
        const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
        std::array<uint32_t, 4> v{};
        for (int k = 0; k < 4; ++k) {
          dvec3 p;
          p[axis] = side == 0 ? lo[axis] : hi[axis];
          p[ua] = (k == 1 || k == 2) ? hi[ua] : lo[ua];
          p[va] = (k >= 2) ? hi[va] : lo[va];
          v[k] = vertex(p, n);
        }
        tri(v[0], v[1], v[2]);
        tri(v[0], v[2], v[3]);
      }
    }
  }

  // Vertical cylinder standing on `base`: smooth sides, flat caps, 4 * segments - 4 tris.
  void addCylinder(const dvec3& base, double radius, double height, int segments) {
    const uint32_t first = static_cast<uint32_t>(positions.size());
    for (int i = 0; i < segments; ++i) {
      const double a = 2.0 * std::numbers::pi * i / segments;
      const dvec3 n(std::cos(a), 0, std::sin(a));
      vertex(base + radius * n, n);
      vertex(base + radius * n + dvec3(0, height, 0), n);
    }
    for (int i = 0; i < segments; ++i) {
      const uint32_t j = static_cast<uint32_t>((i + 1) % segments);
      const uint32_t a0 = first + 2 * static_cast<uint32_t>(i), a1 = a0 + 1;
      const uint32_t b0 = first + 2 * j, b1 = b0 + 1;
      tri(a0, b0, b1);
      tri(a0, b1, a1);
    }
    for (int cap = 0; cap < 2; ++cap) {
      const dvec3 n(0, cap == 0 ? -1.0 : 1.0, 0);
      const uint32_t capFirst = static_cast<uint32_t>(positions.size());
      for (int i = 0; i < segments; ++i) {
        vertex(positions[first + 2 * static_cast<uint32_t>(i) + static_cast<uint32_t>(cap)], n);
      }
      for (int i = 1; i + 1 < segments; ++i) {
        tri(capFirst, capFirst + static_cast<uint32_t>(i), capFirst + static_cast<uint32_t>(i + 1));
      }
    }
  }

  // UV sphere: slices * (2 * stacks - 2) triangles.
  void addSphere(const dvec3& centre, double radius, int slices, int stacks) {
    const uint32_t first = static_cast<uint32_t>(positions.size());
    for (int j = 0; j <= stacks; ++j) {
      const double phi = std::numbers::pi * j / stacks;
      for (int i = 0; i <= slices; ++i) {
        const double theta = 2.0 * std::numbers::pi * i / slices;
        const dvec3 n(std::sin(phi) * std::cos(theta), std::cos(phi),
                      std::sin(phi) * std::sin(theta));
        vertex(centre + radius * n, n);
      }
    }
    const uint32_t row = static_cast<uint32_t>(slices + 1);
    for (uint32_t j = 0; j < static_cast<uint32_t>(stacks); ++j) {
      for (uint32_t i = 0; i < static_cast<uint32_t>(slices); ++i) {
        const uint32_t a = first + j * row + i, b = a + 1, c = a + row, d = c + 1;
        if (j != 0) tri(a, b, d);  // the pole rows collapse to single triangles
        if (j + 1 != static_cast<uint32_t>(stacks)) tri(a, d, c);
      }
    }
  }

  scene::Aabb bounds() const {
    scene::Aabb b = scene::Aabb::emptyBox();
    for (const dvec3& p : positions) b.extend(p);
    return b;
  }

  core::Mesh toRaster() const {
    core::Mesh m;
    for (const dvec3& p : positions) m.positions.push_back(scene::toVec3(p));
    m.indices = indices;
    return m;
  }
};

// A chair with a ball on its seat, standing on the floor at (x, 0, z): about 500
// triangles, the size Gibson 2003 §7.2 gives for occluder proxies (100-500 triangles).
ObjectMesh makeChair(double x, double z) {
  ObjectMesh m;
  const double half = 0.24, legR = 0.025, seatY = 0.45, seatT = 0.05;
  for (int i = 0; i < 4; ++i) {
    const double lx = x + (i % 2 == 0 ? -1 : 1) * (half - legR - 0.01);
    const double lz = z + (i < 2 ? -1 : 1) * (half - legR - 0.01);
    m.addCylinder(dvec3(lx, 0, lz), legR, seatY, 12);
  }
  m.addBox(scene::Aabb{dvec3(x - half, seatY, z - half), dvec3(x + half, seatY + seatT, z + half)});
  for (int i = 0; i < 2; ++i) {
    const double px = x + (i == 0 ? -1 : 1) * (half - legR - 0.01);
    m.addCylinder(dvec3(px, seatY + seatT, z + half - legR - 0.01), legR, 0.5, 12);
  }
  m.addBox(scene::Aabb{dvec3(x - half + 0.02, 0.72, z + half - 0.06),
                       dvec3(x + half - 0.02, 0.95, z + half - 0.02)});
  m.addSphere(dvec3(x - 0.05, seatY + seatT + 0.12, z - 0.05), 0.12, 14, 8);
  return m;
}

// ---------------------------------------------------------------------------------------
// Lighting: diffuse emitters of the patch mesh, point-to-patch form factors (§5).

struct Emitter {
  uint32_t patch;
  dvec3 centre, normal, emission;
  double area;
};

class Lighting {
 public:
  Lighting(const scene::RoomDescription& room, const scene::PatchMesh& mesh) : room_(room) {
    for (uint32_t i = 0; i < mesh.patches.size(); ++i) {
      const scene::Patch& p = mesh.patches[i];
      if (p.emits()) emitters_.push_back({i, p.centre, p.normal, p.emission, p.area});
    }
  }

  const std::vector<Emitter>& emitters() const { return emitters_; }

  // Radiance reflected at x (normal n, reflectance rho) from one emitter: the product's
  // transfer (shadow/patch_transfer.h, rho * L_e * F(x, patch)) times visibility.
  dvec3 transfer(const dvec3& x, const dvec3& n, const dvec3& rho, const Emitter& e) const {
    const dvec3 t = shadow::unshadowedTransfer(x, n, rho, e.emission, e.centre, e.normal, e.area);
    if (t == dvec3(0.0)) return t;  // facing away (F = 0): no shadow ray needed
    // Start the shadow ray a hair off the surface so the receiver's own box face does not
    // count as a blocker.
    if (room_.segmentBlocked(x + 1e-6 * n, e.centre)) return dvec3(0.0);
    return t;
  }

  // Sum over all emitters of L_e F V (the "irradiance / pi" seen by x), without rho.
  dvec3 gathered(const dvec3& x, const dvec3& n) const {
    dvec3 sum(0.0);
    for (const Emitter& e : emitters_) sum += transfer(x, n, dvec3(1.0), e);
    return sum;
  }

  // Total radiance towards the camera: emission + rho * (direct + ambient). The ambient
  // term stands in for the indirect light a real photograph would have.
  dvec3 radiance(const dvec3& x, const dvec3& n, const scene::Material& m) const {
    return m.emission + m.reflectance * (gathered(x, n) + ambient);
  }

  dvec3 ambient{0.0};

 private:
  const scene::RoomDescription& room_;
  std::vector<Emitter> emitters_;
};

// ---------------------------------------------------------------------------------------
// A lit scene and the Gibson pipeline that turns it into a trace.

struct SourceQuota {
  uint32_t quad;  // emitting patches of this quad
  int count;      // how many of them become passes
};

struct LitScene {
  std::string name;
  uint32_t width = 0, height = 0;
  scene::RoomDescription room;
  double patchSize = 0.5;
  scene::Camera camera;
  ObjectMesh object;
  dvec3 objectReflectance{0.6};
  std::vector<SourceQuota> quotas;
  uint32_t shadowMapSize = 256;
  float depthBias = 0.002f;
  std::vector<bool> pcf;          // per pass (in pass order); the last entry repeats
  double ambientFraction = 0.15;  // ambient = this * mean direct light on the room
  double middleGrey = 0.18;       // exposure maps the mean room radiance to this
  int supersample = 2;            // background rays per pixel side
};

raster::FrameTrace buildLitTrace(const LitScene& s, size_t& receiverTriangles) {
  const scene::PatchMesh mesh = scene::buildPatchMesh(s.room, s.patchSize);
  Lighting light(s.room, mesh);

  // Exposure and ambient from the mean direct light over the non-emitting patches, so
  // every scene lands mid-grey whatever its emitter units.
  dvec3 meanDirect(0.0);
  double meanRadiance = 0;
  size_t count = 0;
  for (const scene::Patch& p : mesh.patches) {
    if (p.emits()) continue;
    const dvec3 g = light.gathered(p.centre, p.normal);
    meanDirect += g;
    meanRadiance += luminance(p.reflectance * g);
    ++count;
  }
  meanDirect /= static_cast<double>(count);
  meanRadiance /= static_cast<double>(count);
  light.ambient = s.ambientFraction * meanDirect;
  const shadow::ToneCurve tone =
      shadow::ToneCurve::gamma(s.middleGrey / (meanRadiance * (1 + s.ambientFraction)));

  raster::FrameTrace trace;
  trace.view.width = s.width;
  trace.view.height = s.height;
  trace.view.cameraViewProj = s.camera.rasterViewProj();
  trace.view.staticMesh = mesh.toRasterMesh();

  // Background: the empty room as the camera would photograph it.
  trace.frame.background.resize(size_t{s.width} * s.height * 4);
  const int ss = s.supersample;
  for (uint32_t py = 0; py < s.height; ++py) {
    for (uint32_t px = 0; px < s.width; ++px) {
      dvec3 sum(0.0);
      for (int j = 0; j < ss; ++j) {
        for (int i = 0; i < ss; ++i) {
          const double xw = px + (i + 0.5) / ss, yw = py + (j + 0.5) / ss;
          const dvec3 dir = s.camera.rayDirection(xw, yw, s.width, s.height);
          const auto hit = s.room.intersect(s.camera.eye, dir, 0.0, 1e9);
          if (!hit) continue;  // nothing there: black
          const scene::Quad& q = s.room.quads[hit->quad];
          sum += light.radiance(hit->point, hit->normal, q.materialAt(hit->s, hit->u));
        }
      }
      const Rgb8 c = tone.map(sum / static_cast<double>(ss * ss));
      uint8_t* out = &trace.frame.background[(size_t{py} * s.width + px) * 4];
      out[0] = c.r;
      out[1] = c.g;
      out[2] = c.b;
      out[3] = 255;
    }
  }

  // The synthetic object: shaded by the same sources (no self-shadowing), tone-mapped,
  // and reused as its own occluder proxy.
  raster::ShadedMesh shaded;
  shaded.mesh = s.object.toRaster();
  for (size_t v = 0; v < s.object.positions.size(); ++v) {
    const dvec3 g = light.gathered(s.object.positions[v], s.object.normals[v]);
    shaded.colours.push_back(tone.map(s.objectReflectance * (g + light.ambient)));
  }
  trace.frame.objects.push_back(std::move(shaded));
  trace.frame.occluders.push_back(s.object.toRaster());
  const scene::Aabb bounds = s.object.bounds();
  const dvec3 target = bounds.centre();

  // Source selection: per quota, the emitting patches of that quad by decreasing power
  // towards the object (luminance * area * cos / r^2), ties by patch id.
  struct Source {
    Emitter emitter;
    shadow::LightFrustum frustum;
    std::vector<uint32_t> receivers;
    double averageTransfer = 0;
  };
  std::vector<Source> sources;
  scene::Aabb roomBounds = scene::Aabb::emptyBox();
  for (const dvec3& p : mesh.positions) roomBounds.extend(p);
  const double far = glm::length(roomBounds.size()) * 1.5;
  for (const SourceQuota& quota : s.quotas) {
    std::vector<std::pair<double, const Emitter*>> ranked;
    for (const Emitter& e : light.emitters()) {
      if (mesh.patches[e.patch].quad != quota.quad) continue;
      const dvec3 d = target - e.centre;
      const double cosJ = std::max(0.0, glm::dot(e.normal, glm::normalize(d)));
      ranked.emplace_back(-luminance(e.emission) * e.area * cosJ / glm::dot(d, d), &e);
    }
    std::stable_sort(ranked.begin(), ranked.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    int taken = 0;
    for (const auto& [power, e] : ranked) {
      if (taken == quota.count) break;
      const auto frustum = shadow::fitLightFrustum(e->centre, bounds, far);
      if (!frustum) continue;  // source inside the object's sphere: no shadow map
      sources.push_back(Source{*e, *frustum, {}, 0});
      ++taken;
    }
  }

  // Receivers: static triangles inside the light frustum beyond the object's near
  // depth, not emitters, facing the source.
  std::set<uint32_t> unionReceivers;
  for (Source& src : sources) {
    for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
      const scene::Patch& p = mesh.patches[mesh.trianglePatch[t]];
      if (p.emits()) continue;
      const dvec3& a = mesh.positions[mesh.indices[3 * t]];
      const dvec3& b = mesh.positions[mesh.indices[3 * t + 1]];
      const dvec3& c = mesh.positions[mesh.indices[3 * t + 2]];
      if (glm::dot(p.normal, src.emitter.centre - (a + b + c) / 3.0) <= 0) continue;
      if (!shadow::triangleMayReceive(src.frustum.viewProj, a, b, c)) continue;
      src.receivers.push_back(t);
      unionReceivers.insert(t);
    }
  }

  // §7.1.1 pre-process: sort the sources by decreasing average transfer to the receiver
  // set (all receiver vertices of the frame).
  std::set<uint32_t> receiverVertices;
  for (uint32_t t : unionReceivers) {
    for (int k = 0; k < 3; ++k) receiverVertices.insert(mesh.indices[3 * t + k]);
  }
  for (Source& src : sources) {
    double sum = 0;
    for (uint32_t v : receiverVertices) {
      sum += luminance(light.transfer(mesh.positions[v], mesh.normals[v], dvec3(1.0), src.emitter));
    }
    src.averageTransfer =
        receiverVertices.empty() ? 0 : sum / static_cast<double>(receiverVertices.size());
  }
  std::stable_sort(sources.begin(), sources.end(), [](const Source& a, const Source& b) {
    return a.averageTransfer > b.averageTransfer;
  });
  std::vector<uint8_t> sets;
  sets.reserve(sources.size());
  for (const Source& src : sources) {
    sets.push_back(static_cast<uint8_t>(shadow::sourceSet(kSetSeed, src.emitter.patch)));
  }

  // Fig. 4 at every corner of every receiver triangle: L_i is the same radiance the
  // background shows there; L_ij the transfer of each source, in the sorted order.
  // Shared vertices of equal material get equal S because the computation is a pure
  // function of position, normal and reflectance.
  std::map<uint32_t, std::array<std::vector<Rgb8>, 3>> cornerS;
  std::vector<dvec3> transfers(sources.size());
  for (uint32_t t : unionReceivers) {
    const scene::Patch& p = mesh.patches[mesh.trianglePatch[t]];
    auto& corners = cornerS[t];
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh.indices[3 * t + k];
      const dvec3& x = mesh.positions[v];
      const dvec3& n = mesh.normals[v];
      const dvec3 total = p.emission + p.reflectance * (light.gathered(x, n) + light.ambient);
      for (size_t j = 0; j < sources.size(); ++j) {
        transfers[j] = light.transfer(x, n, p.reflectance, sources[j].emitter);
      }
      corners[k].resize(sources.size());
      shadow::intensityTransfers(total, transfers, sets, tone, corners[k]);
    }
  }

  for (size_t j = 0; j < sources.size(); ++j) {
    raster::ShadowPass pass;
    pass.lightViewProj = sources[j].frustum.rasterViewProj;
    pass.shadowMapSize = s.shadowMapSize;
    pass.depthBias = s.depthBias;
    pass.pcf2x2 = s.pcf.empty() ? false : s.pcf[std::min(j, s.pcf.size() - 1)];
    pass.occluder = 0;
    pass.receiverTriangles = sources[j].receivers;
    for (uint32_t t : sources[j].receivers) {
      for (int k = 0; k < 3; ++k)
        pass.receiverS.push_back(core::Rgb16::fromLevels(cornerS[t][k][j]));
    }
    receiverTriangles += pass.receiverTriangles.size();
    trace.frame.passes.push_back(std::move(pass));
  }
  return trace;
}

// ---------------------------------------------------------------------------------------
// The scenes.

scene::Material diffuse(double r, double g, double b) {
  return {dvec3(r, g, b), dvec3(0.0)};
}
scene::Material emitter(const dvec3& radiance) {
  return {dvec3(0.0), radiance};
}

// Region from world-space extents along a quad's two edges (metres from its origin).
scene::Region regionMetres(const scene::Quad& q, const std::string& name, double u0, double u1,
                           double v0, double v1, const scene::Material& m, double patchSize) {
  const double lu = glm::length(q.edgeU), lv = glm::length(q.edgeV);
  return scene::Region{name, u0 / lu, u1 / lu, v0 / lv, v1 / lv, m, patchSize};
}

// The showroom: 6 x 3 x 5 m room, a desk, a window and four ceiling panels, a chair in the
// middle, 50 sources (30 ceiling, 20 window). The benchmark frame is 640x480; the same room
// and passes at 1280x720 and 1920x1080 (the camera's vertical field of view kept, so the
// wider frames see more of the room's sides) measure how the rasterizer scales with pixels.
LitScene showroomScene(uint32_t width, uint32_t height, const std::string& name) {
  LitScene s;
  s.name = name;
  s.width = width;
  s.height = height;
  s.patchSize = 0.45;
  const uint32_t floor =
      s.room.addRoomShell(scene::Aabb{dvec3(0, 0, 0), dvec3(6, 3, 5)}, diffuse(0.45, 0.38, 0.30),
                          diffuse(0.72, 0.71, 0.68), diffuse(0.80, 0.80, 0.80));
  const uint32_t ceiling = floor + 1, windowWall = floor + 5;  // wall z = 5 faces -z
  // Ceiling: edgeU = +x, edgeV = +z. Four 0.6 m panels, 3 x 3 patches each.
  scene::Quad& c = s.room.quads[ceiling];
  int panel = 0;
  for (double px : {1.8, 3.6}) {
    for (double pz : {1.4, 3.0}) {
      c.regions.push_back(regionMetres(c, "light" + std::to_string(panel++), px, px + 0.6, pz,
                                       pz + 0.6, emitter(dvec3(14.0, 13.0, 11.5)), 0.2));
    }
  }
  // Window in the far wall (edgeU = +y, edgeV = +x): 1.6 m wide, sill 0.9 m, 1.2 m tall.
  scene::Quad& w = s.room.quads[windowWall];
  w.regions.push_back(
      regionMetres(w, "window", 0.9, 2.1, 2.7, 4.3, emitter(dvec3(5.0, 6.0, 7.5)), 0.2));
  s.room.addSolidBox("desk", scene::Aabb{dvec3(4.4, 0, 3.4), dvec3(5.8, 0.75, 4.2)},
                     diffuse(0.50, 0.33, 0.20), false);

  s.camera.eye = dvec3(0.35, 1.6, 0.35);
  s.camera.target = dvec3(3.2, 0.7, 2.8);
  s.camera.fovYDegrees = 60;
  s.camera.aspect = double(width) / double(height);
  s.camera.zNear = 0.05;
  s.camera.zFar = 15;

  s.object = makeChair(3.0, 2.4);
  s.objectReflectance = dvec3(0.62, 0.36, 0.20);
  s.quotas = {{ceiling, 30}, {windowWall, 20}};
  s.shadowMapSize = 256;
  s.depthBias = 0.002f;
  s.pcf = {true};
  return s;
}

// 64x48: a floor quad under one small light, a box on the floor; one binary and one PCF
// pass.
LitScene tinyScene() {
  LitScene s;
  s.name = "tiny";
  s.width = 64;
  s.height = 48;
  s.patchSize = 0.25;
  const uint32_t floor = s.room.addQuad(scene::Quad{
      "floor", dvec3(-1, 0, -1), dvec3(0, 0, 2), dvec3(2, 0, 0), diffuse(0.6, 0.55, 0.5), {}, {}});
  // Light facing down (cross(+x, +z) = -y), 0.5 m square at 1.6 m, behind and left of the
  // box so its shadow falls towards the camera.
  const uint32_t lamp = s.room.addQuad(scene::Quad{"lamp",
                                                   dvec3(-0.9, 1.6, -0.9),
                                                   dvec3(0.5, 0, 0),
                                                   dvec3(0, 0, 0.5),
                                                   emitter(dvec3(20, 19, 17)),
                                                   {},
                                                   {}});
  (void)floor;
  s.camera.eye = dvec3(0.0, 1.5, 2.0);
  s.camera.target = dvec3(0.0, 0.0, 0.0);
  s.camera.aspect = 64.0 / 48.0;
  s.camera.fovYDegrees = 55;
  s.object.addBox(scene::Aabb{dvec3(-0.15, 0, -0.15), dvec3(0.15, 0.3, 0.15)});
  s.objectReflectance = dvec3(0.3, 0.5, 0.7);
  s.quotas = {{lamp, 2}};
  s.depthBias = 0.002f;
  s.pcf = {false, true};
  return s;
}

// 160x120: a room corner (floor and two walls) lit from above, a column with a ball next
// to the wall; four PCF passes.
LitScene pcfScene() {
  LitScene s;
  s.name = "pcf";
  s.width = 160;
  s.height = 120;
  s.patchSize = 0.35;
  s.room.addQuad(scene::Quad{"floor",
                             dvec3(0, 0, 0),
                             dvec3(0, 0, 2.4),
                             dvec3(2.4, 0, 0),
                             diffuse(0.55, 0.5, 0.45),
                             {},
                             {}});
  s.room.addQuad(scene::Quad{"wall_x0",
                             dvec3(0, 0, 0),
                             dvec3(0, 1.8, 0),
                             dvec3(0, 0, 2.4),
                             diffuse(0.7, 0.7, 0.65),
                             {},
                             {}});
  s.room.addQuad(scene::Quad{"wall_z0",
                             dvec3(0, 0, 0),
                             dvec3(2.4, 0, 0),
                             dvec3(0, 1.8, 0),
                             diffuse(0.65, 0.68, 0.7),
                             {},
                             {}});
  const uint32_t lamp = s.room.addQuad(scene::Quad{"lamp",
                                                   dvec3(0.9, 2.2, 0.8),
                                                   dvec3(0.6, 0, 0),
                                                   dvec3(0, 0, 0.6),
                                                   emitter(dvec3(18, 17, 15)),
                                                   {},
                                                   {}});
  s.camera.eye = dvec3(2.3, 1.3, 2.3);
  s.camera.target = dvec3(0.5, 0.35, 0.7);
  s.camera.aspect = 160.0 / 120.0;
  s.camera.fovYDegrees = 55;
  s.object.addBox(scene::Aabb{dvec3(0.3, 0, 0.9), dvec3(0.5, 0.55, 1.1)});
  s.object.addSphere(dvec3(0.4, 0.65, 1.0), 0.1, 8, 5);
  s.objectReflectance = dvec3(0.7, 0.4, 0.35);
  s.quotas = {{lamp, 4}};
  s.depthBias = 0.002f;
  s.pcf = {true};
  return s;
}

// 128x96 rasterizer edge cases, not a physical scene: a huge ground plane crossing the
// camera's near plane, triangles far off-screen and behind the camera, slivers, zero-area
// triangles (collinear and repeated indices), a shared-edge fan, a wall grid, and a box
// standing exactly on the ground. Three passes from point lights; every static triangle
// inside a light frustum receives, degenerate ones included.
raster::FrameTrace buildEdgesTrace(size_t& receiverTriangles) {
  const uint32_t width = 128, height = 96;
  scene::Camera cam;
  cam.eye = dvec3(0, 1.0, 3.0);
  cam.target = dvec3(0, 0.3, 0);
  cam.aspect = 128.0 / 96.0;
  cam.fovYDegrees = 60;
  cam.zNear = 0.1;
  cam.zFar = 50;

  ObjectMesh stat;  // static mesh with per-vertex normals for the transfers
  auto quadTris = [&](dvec3 a, dvec3 b, dvec3 c, dvec3 d, dvec3 n) {
    const uint32_t i0 = stat.vertex(a, n), i1 = stat.vertex(b, n), i2 = stat.vertex(c, n),
                   i3 = stat.vertex(d, n);
    stat.tri(i0, i1, i2);
    stat.tri(i0, i2, i3);
  };
  const dvec3 up(0, 1, 0);
  // Ground: a 3 m grid of 0.25 m cells round the object (per-vertex S needs vertices
  // near the shadow), inside a 2 km ring of four huge quads that cross the near plane and
  // run far off-screen. The ring meets the grid in T-junctions.
  {
    const uint32_t first = static_cast<uint32_t>(stat.positions.size());
    for (int j = 0; j <= 12; ++j) {
      for (int i = 0; i <= 12; ++i) stat.vertex(dvec3(-1.5 + 0.25 * i, 0, -1.5 + 0.25 * j), up);
    }
    for (uint32_t j = 0; j < 12; ++j) {
      for (uint32_t i = 0; i < 12; ++i) {
        const uint32_t a = first + j * 13 + i;
        stat.tri(a, a + 13, a + 14);
        stat.tri(a, a + 14, a + 1);
      }
    }
    const double k = 1000, g = 1.5;
    quadTris(dvec3(-k, 0, -k), dvec3(-k, 0, k), dvec3(-g, 0, k), dvec3(-g, 0, -k), up);
    quadTris(dvec3(g, 0, -k), dvec3(g, 0, k), dvec3(k, 0, k), dvec3(k, 0, -k), up);
    quadTris(dvec3(-g, 0, g), dvec3(-g, 0, k), dvec3(g, 0, k), dvec3(g, 0, g), up);
    quadTris(dvec3(-g, 0, -k), dvec3(-g, 0, -g), dvec3(g, 0, -g), dvec3(g, 0, -k), up);
  }
  // Back wall grid at z = -1.5 (facing +z), 6 x 3 cells of 0.5 m: shared edges.
  {
    const uint32_t first = static_cast<uint32_t>(stat.positions.size());
    for (int j = 0; j <= 3; ++j) {
      for (int i = 0; i <= 6; ++i)
        stat.vertex(dvec3(-1.5 + 0.5 * i, 0.5 * j, -1.5), dvec3(0, 0, 1));
    }
    for (uint32_t j = 0; j < 3; ++j) {
      for (uint32_t i = 0; i < 6; ++i) {
        const uint32_t a = first + j * 7 + i;
        stat.tri(a, a + 1, a + 8);
        stat.tri(a, a + 8, a + 7);
      }
    }
  }
  // Fan of 12 triangles around one centre, 1 cm above the ground.
  {
    const uint32_t centre = stat.vertex(dvec3(-0.9, 0.01, 0.2), up);
    const uint32_t first = static_cast<uint32_t>(stat.positions.size());
    for (int i = 0; i < 12; ++i) {
      const double a = 2 * std::numbers::pi * i / 12;
      stat.vertex(dvec3(-0.9 + 0.5 * std::cos(a), 0.01, 0.2 + 0.5 * std::sin(a)), up);
    }
    for (uint32_t i = 0; i < 12; ++i) stat.tri(centre, first + i, first + (i + 1) % 12);
  }
  // Slivers: 4 m long, 1 mm and 0.1 mm wide, on the ground plane's left side and upright.
  for (int i = 0; i < 3; ++i) {
    const double z = 0.8 + 0.15 * i, w = i == 0 ? 1e-3 : (i == 1 ? 1e-4 : 3e-3);
    const uint32_t a = stat.vertex(dvec3(-2, 0.02, z), up), b = stat.vertex(dvec3(2, 0.02, z), up),
                   c = stat.vertex(dvec3(0.3, 0.02, z + w), up);
    stat.tri(a, b, c);
  }
  {
    const dvec3 n(0, 0, 1);
    const uint32_t a = stat.vertex(dvec3(1.2, 0.0, -0.5), n),
                   b = stat.vertex(dvec3(1.2, 1.6, -0.5), n),
                   c = stat.vertex(dvec3(1.2005, 0.8, -0.5), n);
    stat.tri(a, b, c);
  }
  // Zero area: collinear, two equal indices, all equal.
  {
    const uint32_t a = stat.vertex(dvec3(-0.5, 0.4, -1.0), up),
                   b = stat.vertex(dvec3(0, 0.6, -1.0), up),
                   c = stat.vertex(dvec3(0.5, 0.8, -1.0), up);
    stat.tri(a, b, c);
    stat.tri(a, a, b);
    stat.tri(c, c, c);
  }
  // Off-screen to the side, and wholly behind the camera.
  quadTris(dvec3(60, 0, -5), dvec3(60, 5, -5), dvec3(70, 5, -5), dvec3(70, 0, -5), dvec3(0, 0, 1));
  quadTris(dvec3(-1, 0.5, 6), dvec3(1, 0.5, 6), dvec3(1, 2, 6), dvec3(-1, 2, 6), dvec3(0, 0, -1));
  // Crossing the near plane beside the eye: from behind the camera to 1.5 m in front.
  {
    const dvec3 n(1, 0, 0);
    const uint32_t a = stat.vertex(dvec3(-0.25, 0.7, 3.6), n),
                   b = stat.vertex(dvec3(-0.25, 1.3, 3.6), n),
                   c = stat.vertex(dvec3(-0.45, 1.0, 1.5), n);
    stat.tri(a, b, c);
  }

  ObjectMesh object;
  object.addBox(scene::Aabb{dvec3(0.2, 0.0, -0.2), dvec3(0.6, 0.5, 0.2)});  // on the ground
  object.addSphere(dvec3(0.4, 0.65, 0.0), 0.15, 10, 6);
  const scene::Aabb bounds = object.bounds();

  raster::FrameTrace trace;
  trace.view.width = width;
  trace.view.height = height;
  trace.view.cameraViewProj = cam.rasterViewProj();
  trace.view.staticMesh = stat.toRaster();
  // A gradient with a checker: easy to see what was subtracted.
  trace.frame.background.resize(size_t{width} * height * 4);
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      uint8_t* p = &trace.frame.background[(size_t{y} * width + x) * 4];
      const bool check = ((x / 8) + (y / 8)) % 2 == 0;
      p[0] = static_cast<uint8_t>(120 + x);
      p[1] = static_cast<uint8_t>(110 + y);
      p[2] = static_cast<uint8_t>(check ? 200 : 160);
      p[3] = 255;
    }
  }
  raster::ShadedMesh shaded;
  shaded.mesh = object.toRaster();
  for (size_t v = 0; v < object.positions.size(); ++v) {
    const dvec3& n = object.normals[v];
    shaded.colours.push_back(Rgb8{static_cast<uint8_t>(140 + 100 * n.x),
                                  static_cast<uint8_t>(140 + 100 * n.y),
                                  static_cast<uint8_t>(140 + 100 * n.z)});
  }
  trace.frame.objects.push_back(std::move(shaded));
  trace.frame.occluders.push_back(object.toRaster());

  // Three small square lights (0.2 m, facing the object), Fig. 4 with a fixed exposure.
  const std::array<dvec3, 3> lights = {dvec3(1.6, 2.4, 1.2), dvec3(-1.2, 2.0, 0.8),
                                       dvec3(0.5, 3.0, -0.6)};
  const shadow::ToneCurve tone = shadow::ToneCurve::gamma(4.0);
  const dvec3 rho(0.6), emission(40.0);
  const double area = 0.04;
  std::vector<uint8_t> sets;
  for (size_t j = 0; j < lights.size(); ++j) {
    sets.push_back(static_cast<uint8_t>(shadow::sourceSet(kSetSeed, j)));
  }
  auto transferAt = [&](const dvec3& x, const dvec3& n, size_t j) {
    const dvec3 ln = glm::normalize(bounds.centre() - lights[j]);
    return shadow::unshadowedTransfer(x, n, rho, emission, lights[j], ln, area);
  };
  const std::array<uint32_t, 3> sizes = {256, 128, 512};
  for (size_t j = 0; j < lights.size(); ++j) {
    const auto frustum = shadow::fitLightFrustum(lights[j], bounds, 60.0);
    raster::ShadowPass pass;
    pass.lightViewProj = frustum->rasterViewProj;
    pass.shadowMapSize = sizes[j];
    pass.depthBias = 0.002f;
    pass.pcf2x2 = j == 1;
    for (uint32_t t = 0; t < stat.indices.size() / 3; ++t) {
      const dvec3& a = stat.positions[stat.indices[3 * t]];
      const dvec3& b = stat.positions[stat.indices[3 * t + 1]];
      const dvec3& c = stat.positions[stat.indices[3 * t + 2]];
      // Pass 0 lists every static triangle (degenerate, off-screen and behind-camera
      // ones included); the others only those the frustum test keeps.
      if (j != 0 && !shadow::triangleMayReceive(frustum->viewProj, a, b, c)) continue;
      pass.receiverTriangles.push_back(t);
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = stat.indices[3 * t + k];
        std::array<dvec3, 3> l{};
        dvec3 total(0.05);
        for (size_t i = 0; i < lights.size(); ++i) {
          l[i] = transferAt(stat.positions[v], stat.normals[v], i);
          total += l[i];
        }
        std::array<Rgb8, 3> out{};
        shadow::intensityTransfers(total, l, sets, tone, out);
        pass.receiverS.push_back(core::Rgb16::fromLevels(out[j]));
      }
    }
    receiverTriangles += pass.receiverTriangles.size();
    trace.frame.passes.push_back(std::move(pass));
  }
  return trace;
}

}  // namespace

std::vector<std::string> syntheticTraceKeys() {
  return {"tiny", "pcf", "showroom", "edges", "showroom-720p", "showroom-1080p"};
}

SyntheticTrace synthesizeTrace(const std::string& key) {
  SyntheticTrace out;
  if (key == "edges") {
    out.name = "edges";
    out.trace = buildEdgesTrace(out.receiverTriangles);
    return out;
  }
  LitScene s;
  if (key == "tiny") {
    s = tinyScene();
  } else if (key == "pcf") {
    s = pcfScene();
  } else if (key == "showroom") {
    s = showroomScene(640, 480, "showroom-50");
  } else if (key == "showroom-720p") {
    s = showroomScene(1280, 720, "showroom-50-720p");
  } else if (key == "showroom-1080p") {
    s = showroomScene(1920, 1080, "showroom-50-1080p");
  } else {
    throw std::invalid_argument("no synthetic trace \"" + key + "\"");
  }
  out.name = s.name;
  out.trace = buildLitTrace(s, out.receiverTriangles);
  return out;
}

}  // namespace penumbra::shadow
