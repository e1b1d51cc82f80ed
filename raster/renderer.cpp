#include "raster/renderer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "raster/job_pool.h"
#include "raster/span_kernels.h"
#include "raster/triangle_setup.h"

namespace penumbra::raster {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr size_t kRowAlign = 64;  // pixels; spec §8

// --- binary64 4x4 helpers for the per-pass lookup matrix (spec §7) ----------------------

using Mat4d = std::array<double, 16>;

Mat4d toDouble(const Mat4& m) {
  Mat4d d;
  for (int i = 0; i < 16; ++i) d[i] = m.m[i];
  return d;
}

Mat4d multiply(const Mat4d& a, const Mat4d& b) {
  Mat4d r;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      r[4 * i + j] = ((a[4 * i] * b[j] + a[4 * i + 1] * b[4 + j]) + a[4 * i + 2] * b[8 + j]) +
                     a[4 * i + 3] * b[12 + j];
    }
  }
  return r;
}

// Inverse by cofactor expansion (fixed order of operations); false if singular.
bool invert(const Mat4d& m, Mat4d& inv) {
  auto at = [&](int r, int c) { return m[4 * r + c]; };
  auto minor3 = [&](int r0, int r1, int r2, int c0, int c1, int c2) {
    return at(r0, c0) * (at(r1, c1) * at(r2, c2) - at(r1, c2) * at(r2, c1)) -
           at(r0, c1) * (at(r1, c0) * at(r2, c2) - at(r1, c2) * at(r2, c0)) +
           at(r0, c2) * (at(r1, c0) * at(r2, c1) - at(r1, c1) * at(r2, c0));
  };
  Mat4d cof;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      int rows[3], cols[3];
      for (int i = 0, k = 0; i < 4; ++i) {
        if (i != r) rows[k++] = i;
      }
      for (int i = 0, k = 0; i < 4; ++i) {
        if (i != c) cols[k++] = i;
      }
      const double minor = minor3(rows[0], rows[1], rows[2], cols[0], cols[1], cols[2]);
      cof[4 * r + c] = ((r + c) % 2 == 0) ? minor : -minor;
    }
  }
  const double det = ((m[0] * cof[0] + m[1] * cof[1]) + m[2] * cof[2]) + m[3] * cof[3];
  if (!(det != 0.0) || !std::isfinite(det)) return false;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) inv[4 * r + c] = cof[4 * c + r] / det;  // adjugate / det
  }
  return true;
}

// A receiver triangle of one pass, ready to draw: which static sub-triangle, its S planes.
struct PassTriangle {
  uint32_t staticSub;
  SpanPlanes s;
};

struct PassWork {
  std::vector<float> shadowMap;
  ShadowLookup lookup{};
  std::vector<PassTriangle> triangles;
  uint64_t mapPixels = 0;
};

struct ObjectTriangle {
  SetupTriangle t;
  SpanPlanes planes;
};

struct TileItem {
  uint32_t pass;  // index into passes
  uint32_t tri;   // index into that pass's triangles
};

// Draws `t` over rows [y0, y1) and columns [x0, x1): `full` means every pixel is covered.
template <class Fn>
void forEachRun(const SetupTriangle& t, int32_t x0, int32_t y0, int32_t x1, int32_t y1, bool full,
                Fn&& fn) {
  const int32_t rowBegin = std::max(y0, t.minY), rowEnd = std::min(y1, t.maxY);
  for (int32_t y = rowBegin; y < rowEnd; ++y) {
    int32_t xa = x0, xb = x1;
    if (full || rowSpan(t, y, x0, x1, xa, xb)) fn(y, xa, xb);
  }
}

}  // namespace

struct Renderer::Impl {
  StaticView view;
  RenderOptions options;
  const SpanKernels* kernels;
  JobPool pool;
  size_t stride;  // pixels per internal row
  int32_t tilesX, tilesY;
  Mat4d windowToWorld;  // C^-1 V^-1 (spec §7)

  // Static cache (spec §6 step 2).
  std::vector<SetupTriangle> staticSubs;
  std::vector<uint32_t> staticSubOwner;      // original triangle index of each sub-triangle
  std::vector<uint32_t> firstSubOfTriangle;  // triangle t -> subs [first[t], first[t+1])
  std::vector<uint32_t> tileListStart;       // sub s -> tileEntries [start[s], start[s+1])
  std::vector<uint32_t> tileEntries;         // tile indices
  std::vector<float> staticDepth;
  std::vector<uint32_t> staticId;
  // Row runs of every static sub-triangle, computed once (spec §4): the camera is fixed, so
  // passes never divide. Sub-triangle s has rows [minY, maxY) at spanStart[s].
  std::vector<uint32_t> spanStart;
  std::vector<std::pair<int32_t, int32_t>> spans;  // [xa, xb); empty runs have xa >= xb

  // Per-frame working state, reused.
  std::vector<uint8_t> rgba;
  std::vector<float> depth;
  std::vector<uint32_t> id;
  std::vector<uint32_t> sScratch;  // packed S of the current pass, zero outside it (spec §6)
  std::vector<ObjectTriangle> objectTriangles;
  std::vector<std::vector<std::pair<uint32_t, bool>>> tileObjects;
  std::vector<std::vector<TileItem>> tileItems;
  std::vector<PassWork> passes;
  std::vector<std::array<uint64_t, 2>> workerCounts;  // object pixels, pass pixels
  FrameStats stats;

  Impl(const StaticView& v, const RenderOptions& o);
  void buildStaticCache();
  void prepareObjects(const FrameContent& frame);
  void preparePass(const FrameContent& frame, size_t index);
  void bin();
  void drawTile(uint32_t tile, const FrameContent& frame, std::span<uint8_t> out, int worker);
};

Renderer::Impl::Impl(const StaticView& v, const RenderOptions& o)
    : view(v), options(o), kernels(nullptr), pool(std::max(1, o.threads)) {
  if (o.threads < 1) throw std::invalid_argument("threads must be at least 1");
  if (o.tileSize != 16 && o.tileSize != 32 && o.tileSize != 64) {
    throw std::invalid_argument("tile size must be 16, 32 or 64");
  }
  if (!simd::isSupported(o.isa)) {
    throw std::invalid_argument(std::string("SIMD target ") + simd::isaName(o.isa) +
                                " is not supported on this CPU or not compiled in");
  }
  kernels = &spanKernelsFor(o.isa);
  FrameTrace probe;
  probe.view = v;
  probe.frame.background.resize(size_t{v.width} * v.height * 4);
  validateTrace(probe, "static view");
  Mat4d cameraInverse;
  if (!invert(toDouble(v.cameraViewProj), cameraInverse)) {
    throw TraceError("static view: camera_view_proj: matrix is singular");
  }
  const double hw = v.width / 2.0, hh = v.height / 2.0;
  const Mat4d viewportInverse = {1.0 / hw, 0, 0, -1, 0, -1.0 / hh, 0, 1, 0, 0, 2, -1, 0, 0, 0, 1};
  windowToWorld = multiply(cameraInverse, viewportInverse);
  stride = (size_t{v.width} + kRowAlign - 1) / kRowAlign * kRowAlign;
  tilesX = static_cast<int32_t>((v.width + o.tileSize - 1) / o.tileSize);
  tilesY = static_cast<int32_t>((v.height + o.tileSize - 1) / o.tileSize);
  rgba.assign(stride * v.height * 4, 0);
  depth.assign(stride * v.height, kInfinity);
  id.assign(stride * v.height, kNoSurface);
  sScratch.assign(stride * v.height, 0);
  tileObjects.resize(size_t(tilesX) * tilesY);
  tileItems.resize(size_t(tilesX) * tilesY);
  workerCounts.resize(size_t(pool.threads()));
  buildStaticCache();
}

void Renderer::Impl::buildStaticCache() {
  const Mesh& mesh = view.staticMesh;
  std::vector<ClipVertex> clip(mesh.positions.size());
  for (size_t i = 0; i < clip.size(); ++i)
    clip[i] = transformPoint(view.cameraViewProj, mesh.positions[i]);
  std::vector<std::array<SnappedVertex, 3>> fan;
  const size_t triangles = mesh.triangleCount();
  firstSubOfTriangle.assign(triangles + 1, 0);
  for (size_t t = 0; t < triangles; ++t) {
    firstSubOfTriangle[t] = static_cast<uint32_t>(staticSubs.size());
    fan.clear();
    clipAndSnapTriangle(
        {clip[mesh.indices[3 * t]], clip[mesh.indices[3 * t + 1]], clip[mesh.indices[3 * t + 2]]},
        view.width, view.height, fan);
    for (const auto& tri : fan) {
      SetupTriangle s;
      if (!setupTriangle(tri, view.width, view.height, s)) continue;
      staticSubs.push_back(s);
      staticSubOwner.push_back(static_cast<uint32_t>(t));
    }
  }
  firstSubOfTriangle[triangles] = static_cast<uint32_t>(staticSubs.size());

  // Depth and ids once, in triangle order (spec §6 step 2).
  staticDepth.assign(stride * view.height, kInfinity);
  staticId.assign(stride * view.height, kNoSurface);
  const int32_t width = static_cast<int32_t>(view.width);
  for (size_t s = 0; s < staticSubs.size(); ++s) {
    const SetupTriangle& t = staticSubs[s];
    const SpanPlanes planes{t.depth, {}, t.minX, t.minY};
    forEachRun(t, 0, 0, width, t.maxY, false, [&](int32_t y, int32_t xa, int32_t xb) {
      kernels->depthLess(staticDepth.data() + stride * y, staticId.data() + stride * y, xa, xb, y,
                         planes, staticSubOwner[s]);
    });
  }

  spanStart.assign(staticSubs.size() + 1, 0);
  for (size_t s = 0; s < staticSubs.size(); ++s) {
    spanStart[s] = static_cast<uint32_t>(spans.size());
    const SetupTriangle& t = staticSubs[s];
    for (int32_t y = t.minY; y < t.maxY; ++y) {
      int32_t xa = 0, xb = 0;
      if (!rowSpan(t, y, 0, width, xa, xb)) xa = xb = 0;
      spans.emplace_back(xa, xb);
    }
  }
  spanStart[staticSubs.size()] = static_cast<uint32_t>(spans.size());

  // Which tiles each sub-triangle touches (binning with trivial reject/accept, spec §4).
  const int32_t ts = options.tileSize;
  tileListStart.assign(staticSubs.size() + 1, 0);
  for (size_t s = 0; s < staticSubs.size(); ++s) {
    tileListStart[s] = static_cast<uint32_t>(tileEntries.size());
    const SetupTriangle& t = staticSubs[s];
    for (int32_t ty = t.minY / ts; ty <= (t.maxY - 1) / ts; ++ty) {
      for (int32_t tx = t.minX / ts; tx <= (t.maxX - 1) / ts; ++tx) {
        const int32_t x0 = tx * ts, y0 = ty * ts;
        const TileCoverage c = classifyTile(t, x0, y0, std::min(x0 + ts, width),
                                            std::min(y0 + ts, static_cast<int32_t>(view.height)));
        if (c == TileCoverage::kNone) continue;
        tileEntries.push_back(static_cast<uint32_t>(ty * tilesX + tx));
      }
    }
  }
  tileListStart[staticSubs.size()] = static_cast<uint32_t>(tileEntries.size());
}

void Renderer::Impl::prepareObjects(const FrameContent& frame) {
  objectTriangles.clear();
  std::vector<ClipVertex> clip;
  std::vector<std::array<SnappedVertex, 3>> fan;
  for (const ShadedMesh& object : frame.objects) {
    const Mesh& mesh = object.mesh;
    clip.resize(mesh.positions.size());
    for (size_t i = 0; i < clip.size(); ++i)
      clip[i] = transformPoint(view.cameraViewProj, mesh.positions[i]);
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
      const uint32_t* idx = &mesh.indices[3 * t];
      fan.clear();
      clipAndSnapTriangle({clip[idx[0]], clip[idx[1]], clip[idx[2]]}, view.width, view.height, fan);
      const Rgb8 c0 = object.colours[idx[0]], c1 = object.colours[idx[1]],
                 c2 = object.colours[idx[2]];
      for (const auto& tri : fan) {
        ObjectTriangle o;
        if (!setupTriangle(tri, view.width, view.height, o.t)) continue;
        o.planes.depth = o.t.depth;
        o.planes.rgb[0] = attributePlane(o.t, {c0.r, c1.r, c2.r});
        o.planes.rgb[1] = attributePlane(o.t, {c0.g, c1.g, c2.g});
        o.planes.rgb[2] = attributePlane(o.t, {c0.b, c1.b, c2.b});
        o.planes.ox = o.t.minX;
        o.planes.oy = o.t.minY;
        objectTriangles.push_back(o);
      }
    }
  }
}

void Renderer::Impl::preparePass(const FrameContent& frame, size_t index) {
  const ShadowPass& pass = frame.passes[index];
  PassWork& work = passes[index];
  const uint32_t size = pass.shadowMapSize;
  const int32_t isize = static_cast<int32_t>(size);

  // Shadow map (spec §6 step 1).
  work.shadowMap.assign(size_t{size} * size, kInfinity);
  work.mapPixels = 0;
  const Mesh& occluder = frame.occluders[pass.occluder];
  std::vector<ClipVertex> clip(occluder.positions.size());
  for (size_t i = 0; i < clip.size(); ++i)
    clip[i] = transformPoint(pass.lightViewProj, occluder.positions[i]);
  std::vector<std::array<SnappedVertex, 3>> fan;
  for (size_t t = 0; t < occluder.triangleCount(); ++t) {
    const uint32_t* idx = &occluder.indices[3 * t];
    fan.clear();
    clipAndSnapTriangle({clip[idx[0]], clip[idx[1]], clip[idx[2]]}, size, size, fan);
    for (const auto& tri : fan) {
      SetupTriangle s;
      if (!setupTriangle(tri, size, size, s)) continue;
      const SpanPlanes planes{s.depth, {}, s.minX, s.minY};
      forEachRun(s, 0, 0, isize, s.maxY, false, [&](int32_t y, int32_t xa, int32_t xb) {
        work.mapPixels += kernels->depthLess(work.shadowMap.data() + size_t{size} * y, nullptr, xa,
                                             xb, y, planes, 0);
      });
    }
  }

  // Camera window space -> light texel space (spec §7).
  const double half = size / 2.0;
  const Mat4d toTexel = {half, 0, 0, half, 0, -half, 0, half, 0, 0, 0.5, 0.5, 0, 0, 0, 1};
  const Mat4d p = multiply(multiply(toTexel, toDouble(pass.lightViewProj)), windowToWorld);
  for (int i = 0; i < 16; ++i) work.lookup.p[i] = static_cast<float>(p[i]);
  work.lookup.map = work.shadowMap.data();
  work.lookup.size = isize;
  work.lookup.bias = pass.depthBias;
  work.lookup.pcf2x2 = pass.pcf2x2;

  // Receiver planes: S per channel on every visible sub-triangle.
  work.triangles.clear();
  for (size_t k = 0; k < pass.receiverTriangles.size(); ++k) {
    const uint32_t t = pass.receiverTriangles[k];
    const Rgb8 s0 = pass.receiverS[3 * k], s1 = pass.receiverS[3 * k + 1],
               s2 = pass.receiverS[3 * k + 2];
    for (uint32_t sub = firstSubOfTriangle[t]; sub < firstSubOfTriangle[t + 1]; ++sub) {
      const SetupTriangle& st = staticSubs[sub];
      PassTriangle pt;
      pt.staticSub = sub;
      pt.s.depth = st.depth;
      pt.s.rgb[0] = attributePlane(st, {s0.r, s1.r, s2.r});
      pt.s.rgb[1] = attributePlane(st, {s0.g, s1.g, s2.g});
      pt.s.rgb[2] = attributePlane(st, {s0.b, s1.b, s2.b});
      pt.s.ox = st.minX;
      pt.s.oy = st.minY;
      work.triangles.push_back(pt);
    }
  }
}

void Renderer::Impl::bin() {
  for (auto& list : tileObjects) list.clear();
  for (auto& list : tileItems) list.clear();
  const int32_t ts = options.tileSize;
  const int32_t width = static_cast<int32_t>(view.width),
                height = static_cast<int32_t>(view.height);
  for (size_t o = 0; o < objectTriangles.size(); ++o) {
    const SetupTriangle& t = objectTriangles[o].t;
    for (int32_t ty = t.minY / ts; ty <= (t.maxY - 1) / ts; ++ty) {
      for (int32_t tx = t.minX / ts; tx <= (t.maxX - 1) / ts; ++tx) {
        const int32_t x0 = tx * ts, y0 = ty * ts;
        const TileCoverage c =
            classifyTile(t, x0, y0, std::min(x0 + ts, width), std::min(y0 + ts, height));
        if (c != TileCoverage::kNone) {
          tileObjects[size_t(ty) * tilesX + tx].push_back(
              {static_cast<uint32_t>(o), c == TileCoverage::kFull});
        }
      }
    }
  }
  for (size_t p = 0; p < passes.size(); ++p) {
    const auto& triangles = passes[p].triangles;
    for (size_t k = 0; k < triangles.size(); ++k) {
      const uint32_t sub = triangles[k].staticSub;
      for (uint32_t e = tileListStart[sub]; e < tileListStart[sub + 1]; ++e) {
        tileItems[tileEntries[e]].push_back({static_cast<uint32_t>(p), static_cast<uint32_t>(k)});
      }
    }
  }
}

void Renderer::Impl::drawTile(uint32_t tile, const FrameContent& frame, std::span<uint8_t> out,
                              int worker) {
  const int32_t ts = options.tileSize;
  const int32_t x0 = static_cast<int32_t>(tile % tilesX) * ts;
  const int32_t y0 = static_cast<int32_t>(tile / tilesX) * ts;
  const int32_t x1 = std::min(x0 + ts, static_cast<int32_t>(view.width));
  const int32_t y1 = std::min(y0 + ts, static_cast<int32_t>(view.height));
  // The tile also owns the row padding right of the image (spec §8).
  const int32_t ownedX1 =
      x1 == static_cast<int32_t>(view.width) ? static_cast<int32_t>(stride) : x1;
  const auto& objects = tileObjects[tile];
  const auto& items = tileItems[tile];

  if (!objects.empty() || !items.empty()) {
    for (int32_t y = y0; y < y1; ++y) {
      const size_t row = stride * y;
      std::memcpy(&rgba[4 * (row + x0)], &frame.background[4 * (size_t{view.width} * y + x0)],
                  4 * size_t(x1 - x0));
      std::memcpy(&depth[row + x0], &staticDepth[row + x0], sizeof(float) * size_t(ownedX1 - x0));
      std::memcpy(&id[row + x0], &staticId[row + x0], sizeof(uint32_t) * size_t(ownedX1 - x0));
    }
    uint64_t objectPixels = 0, passPixels = 0;
    for (const auto& [index, full] : objects) {
      const ObjectTriangle& o = objectTriangles[index];
      forEachRun(o.t, x0, y0, x1, y1, full, [&](int32_t y, int32_t xa, int32_t xb) {
        const size_t row = stride * y;
        objectPixels +=
            kernels->colourLess(&rgba[4 * row], &depth[row], &id[row], xa, xb, y, o.planes);
      });
    }
    // Passes in order; within a pass, S of every receiver run into the scratch buffer,
    // then one shading sweep over the rows the pass touched (spec §6 step 4).
    std::array<int32_t, 64> runBegin, runEnd;
    for (size_t first = 0; first < items.size();) {
      const uint32_t passIndex = items[first].pass;
      const PassWork& pass = passes[passIndex];
      runBegin.fill(x1);
      runEnd.fill(x0);
      int32_t rowLo = y1, rowHi = y0;
      size_t i = first;
      for (; i < items.size() && items[i].pass == passIndex; ++i) {
        const PassTriangle& pt = pass.triangles[items[i].tri];
        const SetupTriangle& t = staticSubs[pt.staticSub];
        const uint32_t owner = staticSubOwner[pt.staticSub];
        const auto* run = &spans[spanStart[pt.staticSub]];
        const int32_t ya = std::max(y0, t.minY), yb = std::min(y1, t.maxY);
        for (int32_t y = ya; y < yb; ++y) {
          const int32_t xa = std::max(x0, run[y - t.minY].first);
          const int32_t xb = std::min(x1, run[y - t.minY].second);
          if (xa >= xb) continue;
          const size_t row = stride * y;
          const uint32_t matched =
              kernels->interpolateS(&sScratch[row], &id[row], xa, xb, y, pt.s, owner);
          if (matched == 0) continue;
          passPixels += matched;
          runBegin[y - y0] = std::min(runBegin[y - y0], xa);
          runEnd[y - y0] = std::max(runEnd[y - y0], xb);
          rowLo = std::min(rowLo, y);
          rowHi = std::max(rowHi, y + 1);
        }
      }
      if (rowLo < rowHi) {
        kernels->shadeRows(rgba.data(), depth.data(), sScratch.data(), stride, rowLo, rowHi,
                           &runBegin[rowLo - y0], &runEnd[rowLo - y0], pass.lookup);
      }
      first = i;
    }
    for (int32_t y = y0; y < y1; ++y) {
      std::memcpy(&out[4 * (size_t{view.width} * y + x0)], &rgba[4 * (stride * y + x0)],
                  4 * size_t(x1 - x0));
    }
    workerCounts[worker][0] += objectPixels;
    workerCounts[worker][1] += passPixels;
  } else {
    for (int32_t y = y0; y < y1; ++y) {
      const size_t offset = 4 * (size_t{view.width} * y + x0);
      std::memcpy(&out[offset], &frame.background[offset], 4 * size_t(x1 - x0));
    }
  }
}

Renderer::Renderer(const StaticView& view, const RenderOptions& options)
    : impl_(std::make_unique<Impl>(view, options)) {}

Renderer::~Renderer() = default;

const FrameStats& Renderer::lastStats() const {
  return impl_->stats;
}
const StaticView& Renderer::view() const {
  return impl_->view;
}

void Renderer::render(const FrameContent& frame, std::span<uint8_t> rgbaOut) {
  Impl& r = *impl_;
  const auto start = Clock::now();
  if (rgbaOut.size() != size_t{r.view.width} * r.view.height * 4) {
    throw std::invalid_argument("render: output buffer has the wrong size");
  }
  validateFrame(frame, r.view.width, r.view.height, r.view.staticMesh.triangleCount(), "frame");

  r.stats = FrameStats{};
  for (auto& c : r.workerCounts) c = {0, 0};
  r.prepareObjects(frame);
  const auto mapsStart = Clock::now();
  r.passes.resize(frame.passes.size());
  r.pool.parallelFor(frame.passes.size(), [&](size_t i, int) { r.preparePass(frame, i); });
  r.stats.msShadowMaps = msSince(mapsStart);
  for (const PassWork& p : r.passes) r.stats.shadowMapPixels += p.mapPixels;
  const auto tilesStart = Clock::now();
  r.bin();
  r.pool.parallelFor(size_t(r.tilesX) * r.tilesY, [&](size_t tile, int worker) {
    r.drawTile(static_cast<uint32_t>(tile), frame, rgbaOut, worker);
  });
  r.stats.msTiles = msSince(tilesStart);
  for (const auto& c : r.workerCounts) {
    r.stats.objectPixels += c[0];
    r.stats.passPixels += c[1];
  }
  r.stats.msTotal = msSince(start);
}

std::vector<uint8_t> renderTrace(const FrameTrace& trace, const RenderOptions& options) {
  Renderer renderer(trace.view, options);
  std::vector<uint8_t> out(size_t{trace.view.width} * trace.view.height * 4);
  renderer.render(trace.frame, out);
  return out;
}

}  // namespace penumbra::raster
